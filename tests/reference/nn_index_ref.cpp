#include "tests/reference/nn_index_ref.h"

#include <algorithm>
#include <array>
#include <bit>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace pg::test::ref {

int grid_key_bits(const Cloud& c) {
    int32_t most[4] = {0, 0, 0, 0};
    for (size_t i = 0; i < c.size(); ++i) {
        for (int a = 0; a < 3; ++a) most[a] = std::max(most[a], c.grid[3 * i + size_t(a)]);
        most[3] = std::max(most[3], c.batch[i]);
    }
    int bits = 0;
    for (int32_t m : most) bits += int(std::bit_width(uint32_t(m)));
    return bits;
}

Cloud random_cloud(size_t n, int clouds, int extent, uint64_t seed, bool distinct) {
    std::mt19937_64 rng(seed);
    const double cells = double(clouds) * extent * extent * extent;
    if (distinct && double(n) > cells) n = size_t(cells);
    Cloud c;
    std::set<std::array<int32_t, 4>> seen;
    while (c.size() < n) {
        std::array<int32_t, 4> p{int32_t(rng() % uint64_t(clouds)), int32_t(rng() % uint64_t(extent)),
                                 int32_t(rng() % uint64_t(extent)), int32_t(rng() % uint64_t(extent))};
        if (distinct && !seen.insert(p).second) continue;
        c.batch.push_back(p[0]);
        c.grid.insert(c.grid.end(), {p[1], p[2], p[3]});
    }
    return c;
}

uint64_t z_order_code(uint32_t x, uint32_t y, uint32_t z, int depth) {
    uint64_t key = 0;
    for (int i = 0; i < depth; ++i)
        key |= uint64_t((x >> i) & 1) << (3 * i + 2) | uint64_t((y >> i) & 1) << (3 * i + 1) |
               uint64_t((z >> i) & 1) << (3 * i);
    return key;
}

uint64_t hilbert_code(uint32_t x, uint32_t y, uint32_t z, int depth) {
    // Bits of each axis, MSB first, as Pointcept's hilbert.encode holds them.
    std::array<std::vector<int>, 3> bits;
    const uint32_t axes[3] = {x, y, z};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < depth; ++b) bits[a].push_back(int((axes[a] >> (depth - 1 - b)) & 1));
    for (int b = 0; b < depth; ++b)
        for (int a = 0; a < 3; ++a) {
            const int mask = bits[a][b];
            for (int l = b + 1; l < depth; ++l) {
                if (mask) {
                    bits[0][l] ^= 1;
                } else {
                    const int flip = bits[0][l] ^ bits[a][l];
                    bits[a][l] ^= flip;
                    bits[0][l] ^= flip;
                }
            }
        }
    // Interleave (bit-major, axis-minor), then Gray to binary: a running xor from the top.
    std::vector<int> gray;
    for (int b = 0; b < depth; ++b)
        for (int a = 0; a < 3; ++a) gray.push_back(bits[a][b]);
    uint64_t code = 0;
    int acc = 0;
    for (int g : gray) {
        acc ^= g;
        code = code << 1 | uint64_t(acc);
    }
    return code;
}

std::vector<uint64_t> serialize_codes(const std::vector<int32_t>& grid, const std::vector<int32_t>& batch, int order,
                                      int depth) {
    std::vector<uint64_t> codes(batch.size());
    const uint64_t mask = depth >= 32 ? ~0u : (uint64_t(1) << depth) - 1;
    for (size_t i = 0; i < batch.size(); ++i) {
        uint32_t x = uint32_t(grid[3 * i]) & mask, y = uint32_t(grid[3 * i + 1]) & mask,
                 z = uint32_t(grid[3 * i + 2]) & mask;
        if (order == 1 || order == 3) std::swap(x, y);
        const uint64_t curve = order < 2 ? z_order_code(x, y, z, depth) : hilbert_code(x, y, z, depth);
        codes[i] = uint64_t(uint32_t(batch[i])) << (3 * depth) | curve;
    }
    return codes;
}

Sorted argsort(const std::vector<uint64_t>& codes, int key_bits) {
    const uint64_t mask = key_bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << key_bits) - 1;
    Sorted s;
    s.order.resize(codes.size());
    std::iota(s.order.begin(), s.order.end(), 0);
    std::stable_sort(s.order.begin(), s.order.end(),
                     [&](int32_t a, int32_t b) { return (codes[a] & mask) < (codes[b] & mask); });
    s.inverse.resize(codes.size());
    for (size_t j = 0; j < codes.size(); ++j) s.inverse[s.order[j]] = int32_t(j);
    return s;
}

Voxels voxelize(const std::vector<int32_t>& grid, const std::vector<int32_t>& batch) {
    using Key = std::array<int32_t, 4>;  // batch, x, y, z: lexicographic order
    auto key = [&](size_t i) { return Key{batch[i], grid[3 * i], grid[3 * i + 1], grid[3 * i + 2]}; };
    std::map<Key, int32_t> first;  // emplace keeps the first, i.e. lowest, point index
    for (size_t i = 0; i < batch.size(); ++i) first.emplace(key(i), int32_t(i));
    Voxels v;
    std::map<Key, int32_t> index;
    for (auto& [key, point] : first) {
        index[key] = int32_t(v.first.size());
        v.first.push_back(point);
        v.batch.push_back(key[0]);
        v.grid.insert(v.grid.end(), {key[1], key[2], key[3]});
    }
    for (size_t i = 0; i < batch.size(); ++i) v.inverse.push_back(index.at(key(i)));
    return v;
}

std::vector<int32_t> neighbor_map(const std::vector<int32_t>& grid, const std::vector<int32_t>& batch, int kernel) {
    using Key = std::array<int32_t, 4>;
    std::map<Key, int32_t> at;
    for (size_t i = 0; i < batch.size(); ++i)
        at.emplace(Key{batch[i], grid[3 * i], grid[3 * i + 1], grid[3 * i + 2]}, int32_t(i));
    const int k = kernel, h = kernel / 2;
    std::vector<int32_t> nbr(batch.size() * k * k * k, -1);
    for (size_t i = 0; i < batch.size(); ++i)
        for (int rx = 0; rx < k; ++rx)
            for (int ry = 0; ry < k; ++ry)
                for (int rz = 0; rz < k; ++rz) {
                    const Key q{batch[i], grid[3 * i] + rx - h, grid[3 * i + 1] + ry - h, grid[3 * i + 2] + rz - h};
                    auto it = at.find(q);
                    if (it != at.end()) nbr[i * k * k * k + (rx * k + ry) * k + rz] = it->second;
                }
    return nbr;
}

Clusters pool_clusters(const std::vector<uint64_t>& code, int shift) {
    std::map<uint64_t, std::vector<int32_t>> groups;
    for (size_t i = 0; i < code.size(); ++i) groups[code[i] >> shift].push_back(int32_t(i));
    Clusters c;
    c.cluster.resize(code.size());
    c.ptr.push_back(0);
    for (auto& [key, points] : groups) {
        for (int32_t p : points) c.cluster[p] = int32_t(c.head.size());
        c.head.push_back(points.front());
        c.members.insert(c.members.end(), points.begin(), points.end());
        c.ptr.push_back(int32_t(c.members.size()));
    }
    return c;
}

std::vector<float> segment_max(const std::vector<float>& x, int channels, const Clusters& c) {
    std::vector<float> y;
    for (size_t m = 0; m + 1 < c.ptr.size(); ++m)
        for (int ch = 0; ch < channels; ++ch) {
            float best = x[size_t(c.members[c.ptr[m]]) * channels + ch];
            for (int j = c.ptr[m] + 1; j < c.ptr[m + 1]; ++j)
                best = std::max(best, x[size_t(c.members[j]) * channels + ch]);
            y.push_back(best);
        }
    return y;
}

}  // namespace pg::test::ref
