#include "app/viewer/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

#include "dataset/orbit.h"
#include "dataset/up_axis.h"

namespace pg::viewer {

namespace {
constexpr double kMaxPitch = 89.0;  // at the pole the horizon (and so the right vector) is undefined
}

OrbitCamera::OrbitCamera(glm::dvec3 up) : up_(glm::normalize(up)) { data::horizontal_axes(up_, a_, b_); }

glm::dvec3 OrbitCamera::forward() const {
    const double y = glm::radians(yaw_), p = glm::radians(pitch_);
    // The eye sits at target + distance * dir; the camera looks back along -dir.
    const glm::dvec3 dir = std::cos(p) * (std::cos(y) * a_ + std::sin(y) * b_) + std::sin(p) * up_;
    return -dir;
}

glm::dvec3 OrbitCamera::eye() const { return target_ - distance_ * forward(); }

void OrbitCamera::look_at(glm::dvec3 eye, glm::dvec3 target) {
    target_ = target;
    glm::dvec3 d = eye - target;
    distance_ = std::max(1e-6, glm::length(d));
    d /= distance_;
    pitch_ = std::clamp(glm::degrees(std::asin(std::clamp(glm::dot(d, up_), -1.0, 1.0))), -kMaxPitch, kMaxPitch);
    yaw_ = glm::degrees(std::atan2(glm::dot(d, b_), glm::dot(d, a_)));
}

void OrbitCamera::match(const data::Camera& camera, double distance) {
    const glm::dvec3 eye = camera.position();
    look_at(eye, eye + std::max(distance, 1e-6) * camera.forward());
}

void OrbitCamera::orbit(double yaw_degrees, double pitch_degrees) {
    yaw_ = std::remainder(yaw_ + yaw_degrees, 360.0);
    pitch_ = std::clamp(pitch_ + pitch_degrees, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(double right, double down) {
    const data::Camera c = camera(2, 2, 60);
    target_ += distance_ * (right * glm::transpose(c.R)[0] + down * glm::transpose(c.R)[1]);
}

void OrbitCamera::dolly(double factor) { distance_ = std::clamp(distance_ * factor, 1e-4, 1e7); }

void OrbitCamera::fly(glm::dvec3 v) {
    const data::Camera c = camera(2, 2, 60);
    const glm::dmat3 to_world = glm::transpose(c.R);
    target_ += distance_ * (to_world * v);
}

data::Camera OrbitCamera::camera(int width, int height, double fov_y_degrees, const std::string& name) const {
    const double fov_y = glm::radians(fov_y_degrees);
    const double fov_x = 2.0 * std::atan(std::tan(0.5 * fov_y) * double(width) / double(height));
    return data::look_at(name, eye(), target_, up_, width, height, glm::degrees(fov_x));
}

}  // namespace pg::viewer
