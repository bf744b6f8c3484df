// Counter-based random numbers: a number is a pure function of (seed, pixel, sample
// index, dimension), so images do not depend on which thread traced which path.
#pragma once
#include <cstdint>

namespace wmlt {

// SplitMix64's finaliser (Steele, Lea and Flood 2014): a strong 64-bit mixer.
inline uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// The key of one path sample.
inline uint64_t sampleKey(uint64_t seed, uint32_t pixel, uint32_t sampleIndex) {
    return mix64(mix64(seed + 0x9e3779b97f4a7c15ull) ^ ((uint64_t(pixel) << 32) | sampleIndex));
}

// Dimension `dim` of the sample's primary sample vector, uniform in [0, 1).
inline float sampleDimension(uint64_t key, uint32_t dim) {
    uint64_t h = mix64(key ^ (0xd1b54a32d192ed03ull * (uint64_t(dim) + 1)));
    return float(h >> 40) * 0x1p-24f;  // 24 random bits: exactly representable, < 1
}

}  // namespace wmlt
