#pragma once
// The free viewer camera: orbits a target about the scene's up axis (no roll), pans in the
// view plane, dollies toward the target, and flies (moves eye and target together).
#include <string>

#include <glm/glm.hpp>

#include "dataset/camera.h"

namespace pg::viewer {

class OrbitCamera {
public:
    explicit OrbitCamera(glm::dvec3 up = {0, -1, 0});

    // Looks at `target` from `eye`.
    void look_at(glm::dvec3 eye, glm::dvec3 target);
    // Takes a dataset camera's pose; the target lies `distance` ahead.
    void match(const data::Camera& camera, double distance);

    void orbit(double yaw_degrees, double pitch_degrees);
    void pan(double right, double down);          // in units of the target distance
    void dolly(double factor);                    // distance *= factor
    void fly(glm::dvec3 along_view_right_down_forward);  // in units of the target distance

    glm::dvec3 eye() const;
    glm::dvec3 target() const { return target_; }
    glm::dvec3 forward() const;
    double distance() const { return distance_; }
    glm::dvec3 up() const { return up_; }

    // An OpenCV pinhole camera of this pose for a width x height image.
    data::Camera camera(int width, int height, double fov_y_degrees, const std::string& name = "viewer") const;

private:
    glm::dvec3 up_, a_, b_;  // up and two horizontal axes
    glm::dvec3 target_{0.0};
    double yaw_ = 0, pitch_ = 20, distance_ = 1;
};

}  // namespace pg::viewer
