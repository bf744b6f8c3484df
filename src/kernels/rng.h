// Counter-based random numbers: a number is a pure function of (seed, pixel, sample
// index, dimension), so images do not depend on which thread traced which path.
#pragma once
#include <cstddef>
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

// The key of a pixel's strata (kernels/camera.h): one per seed and pixel.
inline uint64_t strataKey(uint64_t seed, uint32_t pixel) { return mix64(mix64(seed ^ 0x5851f42d4c957f2dull) + pixel); }

// Element i of a pseudo-random permutation of [0, n), n >= 1, chosen by `key`: a balanced
// Feistel network of 8 rounds (Luby and Rackoff 1988; round function mix64) on the smallest
// even number of bits w with 2^w >= n, applied again to values >= n until one falls below n
// (cycle walking: a bijection of [0, n), on average fewer than 4 steps since 2^w < 4 n),
// then rotated by a shift c uniform in [0, n) from an independent hash of the key: so
// pi(i) is exactly uniform over keys for every i, however weak the Feistel network is for
// tiny n (its halves are 2 bits wide for n = 9).
struct Permutation {
    uint32_t n = 1, half = 1, mask = 1, shift = 0;
    uint64_t key = 0;
    // The network for n and key, made once for all the indices it permutes.
    Permutation() = default;
    Permutation(uint32_t n_, uint64_t key_) : n(n_), key(key_) {
        if (n <= 1) return;
        while ((uint64_t(1) << (2 * half)) < n) ++half;
        mask = (1u << half) - 1;
        shift = uint32_t(mix64(key ^ 0xa0761d6478bd642full) % n);
    }
    uint32_t operator()(uint32_t i) const {
        if (n <= 1) return 0;
        do i = network(i, key, half, mask);
        while (i >= n);
        return rotate(i);
    }
    // The last step: the rotation by shift of a value the walk left below n.
    uint32_t rotate(uint32_t i) const { return i + shift < n ? i + shift : i + shift - n; }
    // One pass through the network (2 half bits wide), no walk.
    static uint32_t network(uint32_t i, uint64_t key, uint32_t half, uint32_t mask) {
        uint32_t l = i >> half, r = i & mask;
        for (uint64_t round = 0; round < 8; ++round) {
            const uint32_t f = uint32_t(mix64(key + round * 0x9e3779b97f4a7c15ull + r)) & mask;
            const uint32_t next = l ^ f;
            l = r;
            r = next;
        }
        return (l << half) | r;
    }
};

inline uint32_t permuteIndex(uint32_t i, uint32_t n, uint64_t key) { return Permutation(n, key)(i); }

// Permutation::network on v[j] with key[j], j < m, in place, in one loop the compiler
// vectorises (the walk of the values it leaves >= n is the caller's: permuteWalks).
__attribute__((noinline)) inline void permutationNetworks(uint32_t* __restrict v, const uint64_t* __restrict key, size_t m, uint32_t half,
                                                          uint32_t mask) {
    for (size_t j = 0; j < m; ++j) v[j] = Permutation::network(v[j], key[j], half, mask);
}

// The walks of m indices through permutations of one n (Permutation(n, key[j])): v[j]
// holds index j on entry and at the end the value below n its walk stops at (not yet
// rotated). One flat pass of the networks over all, then over the values still >= n, moved
// to the front of (walkV, walkKey, walkSample) (scratch of m entries), until none is left:
// each pass leaves about a share 1 - n / 2^(2 half) (under 3/4) of its values to the next.
inline void permuteWalks(uint32_t n, uint32_t* __restrict v, const uint64_t* __restrict key, size_t m, uint32_t* __restrict walkV,
                         uint64_t* __restrict walkKey, uint32_t* __restrict walkSample) {
    if (n <= 1) {
        for (size_t j = 0; j < m; ++j) v[j] = 0;
        return;
    }
    const Permutation p(n, 0);  // its half and mask (the same for every key)
    permutationNetworks(v, key, m, p.half, p.mask);
    size_t left = 0;
    for (size_t j = 0; j < m; ++j) {
        if (v[j] < n) continue;
        walkV[left] = v[j];
        walkKey[left] = key[j];
        walkSample[left++] = uint32_t(j);
    }
    while (left > 0) {
        permutationNetworks(walkV, walkKey, left, p.half, p.mask);
        size_t still = 0;
        for (size_t j = 0; j < left; ++j) {
            if (walkV[j] < n) {
                v[walkSample[j]] = walkV[j];
                continue;
            }
            walkV[still] = walkV[j];
            walkKey[still] = walkKey[j];
            walkSample[still++] = walkSample[j];
        }
        left = still;
    }
}

}  // namespace wmlt
