#version 450
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) buffer Out { uint o[]; };
layout(push_constant) uniform Push { uint n; uint mode; } pc;
shared uint s;
void main() {
    uint c = 0u;
    if (gl_LocalInvocationIndex == 0u) s = 0u;
    barrier();
    for (uint i = 0u; i < pc.n; ++i) {
        if (gl_LocalInvocationIndex == 0u) s = s + 1u;
        barrier();
        c += s;
        barrier();
    }
    o[gl_LocalInvocationIndex] = c;
}
