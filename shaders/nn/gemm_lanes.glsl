// One depth chunk of a GEMM, written for CPU Vulkan drivers (lavapipe):
//     y[m, n0 : n0+NC] (+)= A[m, k0 : k0+KC] . W[n0 : n0+NC, k0 : k0+KC]^T
// A is x or x gathered through a neighbour table (gemm_shared.glsl).
//
// Why it is shaped like this: llvmpipe runs invocations as 8-wide SIMD lanes. A memory access
// whose address may differ between lanes is a scalar loop over the lanes (tens of instructions
// per value), and inside any loop or branch every access is. Only an access at the top level
// of the shader whose address comes from constants and push constants is one broadcast. So:
// no loops (the host issues one dispatch per chunk; chunks accumulate in y), one lane per row
// of A, the workgroup stages its weight chunk once in shared memory, and the multiply-adds
// read it at constant offsets - a broadcast that LLVM folds into the multiply. Per-lane
// traffic is then KC values of A and NC of y per KC*NC multiply-adds. GPUs use gemm_tiled.glsl.
//
// Defines: WG (rows per workgroup), KC (chunk depth, a multiple of 32), A_VEC (A, W and the
// gathered rows are read 8 floats at a time: needs cin % 8 == 0 when dense, cin % A_SEG == 0
// when gathered, K % 8 == 0), A_SEG (optional, 32 or 8: columns of A per neighbour lookup;
// 8 lets gathered rows of 8 or 24 channels take vector loads, at a lookup per 8), Y_VEC (y
// rows 8 floats at a time: needs N % 8 == 0), GELU
// (optional: apply GELU before storing; the last chunk's variant. A flag would cost the GELU
// on every chunk: llvmpipe runs both sides of a branch), RULEBOOK (optional, with A_VEC and
// Y_VEC: the rows are the pairs of one tap of a sparse-convolution rulebook, the tap whose
// columns the chunk covers (cin % KC == 0, KC 16 allowed here); each adds its product into y
// at its output row), TAPS (optional, with RULEBOOK: every tap in one dispatch, sized by the
// rulebook's schedule; each tap's products go to its own slice of y at the output rows, chunk
// pc.k0 of each tap's columns, and nn/conv_reduce adds the slices. A dispatch per tap left
// small tables one workgroup, one core, and 27 dispatches' fixed cost per convolution), SPLIT (optional, dense with A_VEC and Y_VEC: the depth is split over the
// workgroups of one dispatch, slice s taking the chunk at pc.k0 + s * pc.slice_k and writing
// its raw sum to y[s]; the host adds the slices. For deep products with few rows and columns, weight
// gradients, where one dispatch per chunk left one workgroup, one core, and the dispatches'
// fixed cost to dominate).
#ifndef SPLIT
#define SPLIT 0
#endif
#ifndef A_SEG
#define A_SEG 32u
#endif
#if SPLIT && (RULEBOOK || !(A_VEC && Y_VEC))
#error "SPLIT is dense, with A_VEC and Y_VEC"
#endif
#ifndef RULEBOOK
#define RULEBOOK 0
#endif
#ifndef TAPS
#define TAPS 0
#endif
#if TAPS && !RULEBOOK
#error "TAPS is a RULEBOOK variant"
#endif
#if RULEBOOK && !(A_VEC && Y_VEC)
#error "RULEBOOK needs A_VEC and Y_VEC"
#endif
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "common/dispatch.glsl"
#include "nn/gemm_shared.glsl"
#if GELU
#include "nn/erf.glsl"
#endif

#define NC PG_LANES_NC
layout(local_size_x = WG) in;

#if A_VEC
layout(std430, binding = 0) readonly buffer XBuf { u64vec4 x8[]; };
layout(std430, binding = 1) readonly buffer WBuf { u64vec4 w8[]; };
#else
layout(std430, binding = 0) readonly buffer XBuf { float x1[]; };
layout(std430, binding = 1) readonly buffer WBuf { float w1[]; };
#endif
layout(std430, binding = 2) readonly buffer BiasBuf { float bias[]; };
#if Y_VEC
layout(std430, binding = 3) readonly buffer ResBuf { u64vec4 res8[]; };
layout(std430, binding = 4) buffer YBuf { u64vec4 y8[]; };
#else
layout(std430, binding = 3) readonly buffer ResBuf { float res1[]; };
layout(std430, binding = 4) buffer YBuf { float y1[]; };
#endif
#if RULEBOOK
layout(std430, binding = 5) readonly buffer PairBuf { uvec2 pairs[]; };  // [taps][M]: (output row, input row)
layout(std430, binding = 6) readonly buffer CountBuf { uint counts[]; };  // pairs per tap
#if TAPS
layout(std430, binding = 7) readonly buffer ScheduleBuf { uint schedule[]; };
#endif
#else
layout(std430, binding = 5) readonly buffer NbrBuf { int nbr[]; };
#endif
layout(push_constant) uniform PushBlock { GemmPush pc; };

shared float ws[NC * KC];  // ws[c * KC + kk] = W[n0 + c, k0 + kk], zero outside W
#if !RULEBOOK
shared float bs[NC];  // (rulebook sums start from y, which holds the bias)
#endif

// 8 floats packed in a u64vec4, low word first.
void unpack8(u64vec4 v, out float f[8]) {
    [[unroll]] for (uint j = 0u; j < 4u; ++j) {
        uvec2 p = unpack32(v[j]);
        f[2u * j] = uintBitsToFloat(p.x);
        f[2u * j + 1u] = uintBitsToFloat(p.y);
    }
}

void main() {
    const uint lid = gl_LocalInvocationIndex;
#if SPLIT
    const uint tiles = (pc.M + WG - 1u) / WG * pc.col_tiles;
    const uint slice = pg_group_index() / tiles, g = pg_group_index() % tiles;
    const uint k0 = pc.k0 + slice * pc.slice_k;
    const uint ybase = slice * pc.M * pc.N;  // this slice's y
#elif TAPS
    // The schedule (nn/conv_schedule) numbers every tap's row groups back to back: tap t's from
    // schedule[t] on, the tap of row group r at schedule[taps + 1 + r]. (Leaving early instead,
    // from a dispatch of M / WG row groups for every tap, made llvmpipe run the kernel 8x slower.)
    const uint rg_end = schedule[pc.taps], rg_want = pg_group_index() / pc.col_tiles;
    const uint rg = min(rg_want, max(rg_end, 1u) - 1u);  // a folded dispatch's spare groups store nothing
    const uint tap = schedule[pc.taps + 1u + rg];
    const uint g = (rg - schedule[tap]) * pc.col_tiles + pg_group_index() % pc.col_tiles;
    const uint k0 = tap * pc.cin + pc.k0;
    const uint ybase = tap * pc.M * pc.N;  // this tap's slice
#else
    const uint g = pg_group_index();
    const uint k0 = pc.k0;
    const uint ybase = 0u;
#endif
    const uint n0 = (g % pc.col_tiles) * NC;
#if RULEBOOK
    // Indirect dispatches cover exactly the tap's pairs; lanes past them compute on a copy of
    // its last pair and store nothing.
#if !TAPS
    const uint tap = k0 / pc.cin;
#endif
    const uint first = tap * pc.M, count = counts[tap];
    const uint p = (g / pc.col_tiles) * WG + lid;
    const uvec2 pair = pairs[first + min(p, max(count, 1u) - 1u)];
    const uint mr = pair.x;
#if TAPS
    const bool store = p < count && rg_want < rg_end;
#else
    const bool store = p < count;
#endif
#else
    const uint m = (g / pc.col_tiles) * WG + lid;
    const uint mr = min(m, pc.M - 1u);  // rows past M compute on a copy of the last row
    const bool store = m < pc.M;
    const bool gather = (pc.flags & PG_GEMM_GATHER) != 0u;
#endif

    // Stage W's chunk (zero past N and K) and the bias.
#if A_VEC
    const uint groups = NC * KC / 8u;
    [[unroll]] for (uint r = 0u; r < (groups + WG - 1u) / WG; ++r) {
        const uint i = r * WG + lid;
        if (groups % WG == 0u || i < groups) {
            const uint c = i / (KC / 8u), k = k0 + 8u * (i % (KC / 8u));
            const bool valid = n0 + c < pc.N && k < pc.K;
            float f[8];
            unpack8(w8[(min(n0 + c, pc.N - 1u) * pc.K + min(k, pc.K - 8u)) / 8u], f);
            [[unroll]] for (uint j = 0u; j < 8u; ++j) ws[c * KC + k - k0 + j] = valid ? f[j] : 0.0;
        }
    }
#else
    // Scalar paths are loops: every access is per lane anyway, and unrolled they only make the
    // shader slow to compile.
    [[dont_unroll]] for (uint r = 0u; r < (NC * KC + WG - 1u) / WG; ++r) {
        const uint i = r * WG + lid;
        if ((NC * KC) % WG == 0u || i < NC * KC) {
            const uint c = i / KC, k = k0 + i % KC;
            const bool valid = n0 + c < pc.N && k < pc.K;
            const float v = w1[min(n0 + c, pc.N - 1u) * pc.K + min(k, max(pc.K, 1u) - 1u)];
            ws[i] = valid ? v : 0.0;
        }
    }
#endif
#if !RULEBOOK
    if (lid < NC) {
        const float b = bias[min(n0 + lid, pc.N - 1u)];
        bs[lid] = (pc.flags & PG_GEMM_BIAS) != 0u && n0 + lid < pc.N ? b : 0.0;
    }
#endif
    barrier();

    // This lane's row of A for the chunk, zero past K and for missing neighbours.
    float a[KC];
#if RULEBOOK
    // The chunk lies in one tap (cin % KC == 0): KC columns of the pair's input row.
    [[unroll]] for (uint r = 0u; r < KC / 8u; ++r) {
        float f[8];
        unpack8(x8[(pair.y * pc.cin + k0 % pc.cin) / 8u + r], f);
        [[unroll]] for (uint i = 0u; i < 8u; ++i) a[8u * r + i] = f[i];
    }
#elif A_VEC
    [[unroll]] for (uint q = 0u; q < KC / A_SEG; ++q) {
        // A segment of A_SEG columns lies in one tap: cin % A_SEG == 0 when gathered.
        const uint k = k0 + A_SEG * q;
        const uint t = min(k / pc.cin, pc.taps - 1u), c = k % pc.cin;
        int j = int(mr);
        if (gather) j = nbr[mr * pc.taps + t];
        const bool valid = k < pc.K && j >= 0;
        [[unroll]] for (uint r = 0u; r < A_SEG / 8u; ++r) {
            const uint cr = min(c + 8u * r, pc.cin - 8u);
            float f[8];
            unpack8(x8[(uint(max(j, 0)) * pc.cin + cr) / 8u], f);
            [[unroll]] for (uint i = 0u; i < 8u; ++i) a[A_SEG * q + 8u * r + i] = valid ? f[i] : 0.0;
        }
    }
#else
    [[dont_unroll]] for (uint kk = 0u; kk < KC; ++kk) {
        const uint k = k0 + kk;
        const uint t = min(k / max(pc.cin, 1u), pc.taps - 1u), c = min(k % max(pc.cin, 1u), max(pc.cin, 1u) - 1u);
        int j = int(mr);
        if (gather) j = nbr[mr * pc.taps + t];
        const bool valid = k < pc.K && j >= 0;
        const float v = x1[uint(max(j, 0)) * pc.cin + c];
        a[kk] = valid ? v : 0.0;
    }
#endif

    // Start from the bias (read here, outside any branch, where it is a broadcast), then the
    // residual on the first chunk or the running sum in y on later ones.
    float acc[NC];
#if RULEBOOK
    [[unroll]] for (uint c = 0u; c < NC; ++c) acc[c] = 0.0;  // replaced by y below
#else
    [[unroll]] for (uint c = 0u; c < NC; ++c) acc[c] = bs[c];
#endif
    // (Branches do not skip work in llvmpipe, but an access in one that no lane takes is cheap.)
    if ((pc.flags & PG_GEMM_FIRST) == 0u) {
#if Y_VEC
        [[unroll]] for (uint i = 0u; i < NC / 8u; ++i) {
            float f[8];
            unpack8(y8[(ybase + mr * pc.N + min(n0 + 8u * i, pc.N - 8u)) / 8u], f);
            [[unroll]] for (uint j = 0u; j < 8u; ++j) acc[8u * i + j] = f[j];
        }
#else
        [[unroll]] for (uint c = 0u; c < NC; ++c) acc[c] = y1[mr * pc.N + min(n0 + c, pc.N - 1u)];
#endif
    } else if ((pc.flags & PG_GEMM_RESIDUAL) != 0u) {
#if Y_VEC
        [[unroll]] for (uint i = 0u; i < NC / 8u; ++i) {
            float f[8];
            unpack8(res8[(mr * pc.N + min(n0 + 8u * i, pc.N - 8u)) / 8u], f);
            [[unroll]] for (uint j = 0u; j < 8u; ++j) acc[8u * i + j] += f[j];
        }
#else
        [[unroll]] for (uint c = 0u; c < NC; ++c) acc[c] += res1[mr * pc.N + min(n0 + c, pc.N - 1u)];
#endif
    }

    [[unroll]] for (uint kk = 0u; kk < KC; ++kk)
        [[unroll]] for (uint c = 0u; c < NC; ++c) acc[c] += a[kk] * ws[c * KC + kk];

#if GELU
    [[unroll]] for (uint c = 0u; c < NC; ++c) acc[c] = pg_gelu(acc[c]);
#endif
    if (store) {
#if Y_VEC
        [[unroll]] for (uint i = 0u; i < NC / 8u; ++i)
            if (n0 + 8u * i < pc.N) {
                u64vec4 v;
                [[unroll]] for (uint j = 0u; j < 4u; ++j)
                    v[j] = pack64(uvec2(floatBitsToUint(acc[8u * i + 2u * j]), floatBitsToUint(acc[8u * i + 2u * j + 1u])));
                y8[(ybase + mr * pc.N + n0) / 8u + i] = v;
            }
#else
        [[unroll]] for (uint c = 0u; c < NC; ++c)
            if (n0 + c < pc.N) y1[mr * pc.N + n0 + c] = acc[c];
#endif
    }
}
