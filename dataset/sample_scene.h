#pragma once
// The bundled sample scene: a procedurally generated desk capture (a wooden table top with a
// mug, a ball, a box, a cone and a book, in a simple room), made of surface-aligned flat
// Gaussians, with an orbit of 24 cameras. Units are metres; like a COLMAP capture, world up
// is -y: the table top lies in the plane y = 0 and objects stand at negative y.
// Each Gaussian carries an integer "instance" property: 0 for the table and the room,
// 1..kSampleSceneObjects for the objects. Deterministic for a seed on every platform.
#include <cstdint>
#include <vector>

#include "dataset/camera.h"
#include "dataset/gaussian_cloud.h"

namespace pg::data {

struct SampleScene {
    GaussianCloud cloud;
    std::vector<Camera> cameras;  // view_000 .. view_023, 640x480
};

constexpr int kSampleSceneObjects = 5;  // mug, ball, box, cone, book: instances 1..5

SampleScene make_sample_scene(uint32_t seed = 1);

}  // namespace pg::data
