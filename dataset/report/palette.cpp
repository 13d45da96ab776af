#include "dataset/report/palette.h"

#include <iterator>

#include <algorithm>
#include <cmath>
#include <string>

#include "dataset/error.h"

namespace pg::data::report {

glm::vec3 hsv(float h, float s, float v) {
    h = h - std::floor(h);
    const float k[3] = {5.0f, 3.0f, 1.0f};
    glm::vec3 c;
    for (int i = 0; i < 3; ++i) {
        const float t = std::fmod(k[i] + h * 6.0f, 6.0f);
        c[i] = v - v * s * std::clamp(std::min(t, 4.0f - t), 0.0f, 1.0f);
    }
    return c;
}

glm::vec3 class_colour(int id) {
    static const glm::vec3 palette[] = {{0.5f, 0.5f, 0.5f},   {0.9f, 0.2f, 0.15f}, {0.6f, 0.3f, 0.85f},
                                        {0.2f, 0.8f, 0.2f},   {0.15f, 0.45f, 1.0f}, {1.0f, 0.9f, 0.1f},
                                        {1.0f, 0.55f, 0.1f}};
    if (id >= 0 && id < int(std::size(palette))) return palette[id];
    return glm::vec3(mask_colour(uint16_t(id))) / 255.0f;
}

glm::u8vec3 mask_colour(uint16_t id) {
    if (id == 0) return {0, 0, 0};
    // Golden-ratio hues; saturation and value cycle so neighbours in id differ twice over.
    const float h = std::fmod(0.13f + 0.618034f * float(id), 1.0f);
    const float s = 0.55f + 0.15f * float(id % 3), v = 0.95f - 0.15f * float((id / 3) % 3);
    const glm::vec3 c = hsv(h, s, v);
    return {uint8_t(std::lround(255.0f * c.x)), uint8_t(std::lround(255.0f * c.y)), uint8_t(std::lround(255.0f * c.z))};
}

Image8 colourise_mask(const std::vector<uint16_t>& mask, int width, int height) {
    if (width <= 0 || height <= 0 || mask.size() != size_t(width) * size_t(height))
        throw InputError("mask", "size does not match " + std::to_string(width) + "x" + std::to_string(height));
    Image8 img{width, height, 3, std::vector<uint8_t>(mask.size() * 3)};
    for (size_t i = 0; i < mask.size(); ++i) {
        const glm::u8vec3 c = mask_colour(mask[i]);
        img.pixels[3 * i] = c.x;
        img.pixels[3 * i + 1] = c.y;
        img.pixels[3 * i + 2] = c.z;
    }
    return img;
}


}  // namespace pg::data::report
