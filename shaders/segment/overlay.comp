#version 450
// A picture for the screen: the render with every labelled pixel blended with its object's
// colour and each object's border drawn solid, packed as RGBA8. The GPU twin of
// seg::ViewMask::overlay, byte for byte: the same float operations in the same order
// (`precise`: no fused multiply-add), and lround's rounding.
#extension GL_GOOGLE_include_directive : require
#include "segment/picture_shared.h"

layout(local_size_x = kPictureSide, local_size_y = kPictureSide) in;
layout(std430, binding = 0) readonly buffer Render { vec4 render[]; };  // linear rgb, any range
layout(std430, binding = 1) readonly buffer Labels { uint labels[]; };  // per pixel, 0: none
layout(std430, binding = 2) readonly buffer Palette { vec4 palette[]; };  // rgb, a < 0: hidden
layout(std430, binding = 3) writeonly buffer Picture { uint picture[]; };
layout(push_constant) uniform Push { OverlayPush pc; };

// The label as drawn: hidden objects and labels past the palette are no label.
uint shown(uint x, uint y) {
    uint l = labels[y * pc.width + x];
    return l < pc.palette_size && palette[l].a >= 0.0 ? l : 0u;
}

// std::lround for x >= 0: floor(x + 0.5) would round 0.49999997 up.
uint round_half_up(float x) {
    precise float f = floor(x);
    return uint(f) + (x - f >= 0.5 ? 1u : 0u);
}

void main() {
    uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
    if (x >= pc.width || y >= pc.height) return;
    uint p = y * pc.width + x;
    precise vec3 rgb = clamp(render[p].rgb, 0.0, 1.0);
    uint l = pc.has_labels != 0u ? shown(x, y) : 0u;
    if (l != 0u) {
        vec3 c = palette[l].rgb;
        bool edge = (x > 0u && shown(x - 1u, y) != l) || (x + 1u < pc.width && shown(x + 1u, y) != l) ||
                    (y > 0u && shown(x, y - 1u) != l) || (y + 1u < pc.height && shown(x, y + 1u) != l);
        precise vec3 blend = kOverlayRender * rgb + kOverlayColour * c;
        rgb = edge ? c : blend;
    }
    precise vec3 scaled = rgb * 255.0;
    picture[p] = round_half_up(scaled.r) | round_half_up(scaled.g) << 8 | round_half_up(scaled.b) << 16 | 255u << 24;
}
