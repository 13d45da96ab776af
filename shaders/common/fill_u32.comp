#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Data { uint data[]; };
layout(push_constant) uniform Push { uint n; uint value; } pc;
void main() { uint i = gl_GlobalInvocationID.x; if (i < pc.n) data[i] = pc.value; }
