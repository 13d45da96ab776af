#version 450
// Running statistics of a training-mode BatchNorm, PyTorch's convention:
// running = (1 - m) * running + m * batch, with the unbiased batch variance var * M / (M - 1).
#extension GL_GOOGLE_include_directive : require
#include "common/dispatch.glsl"
#include "nn/grad_shared.glsl"
layout(local_size_x = PG_GRAD_THREADS) in;
layout(std430, binding = 0) readonly buffer MeanBuf { float mean[]; };
layout(std430, binding = 1) readonly buffer VarBuf { float var[]; };
layout(std430, binding = 2) buffer RunMeanBuf { float running_mean[]; };
layout(std430, binding = 3) buffer RunVarBuf { float running_var[]; };
layout(push_constant) uniform PushBlock { RunningStatsPush pc; };

void main() {
    const uint c = pg_global_index();
    if (c >= pc.cols) return;
    const float m = pc.momentum;
    const float unbiased = var[c] * (float(pc.rows) / float(pc.rows - 1u));
    running_mean[c] = (1.0 - m) * running_mean[c] + m * mean[c];
    running_var[c] = (1.0 - m) * running_var[c] + m * unbiased;
}
