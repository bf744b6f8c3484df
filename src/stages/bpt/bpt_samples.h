// Where a BPT walk's primary sample numbers come from (the stages are templates on the
// source, chosen once per tracer): the layout of a BPT sample's streams, hashed from a key
// (BPT: HashedSamples), stored as one strategy's row (MMLT: StrategyLayout, StoredSamples)
// or a whole sample's coordinates proposed as they are read (PSSMLT: WholeLayout,
// WholeSamples).
#pragma once
#include <algorithm>
#include <cstdint>

#include "kernels/chain_numbers.h"
#include "kernels/rng.h"

namespace wmlt {

// Primary sample layout of a BPT sample (keys: bptSampleKey, a stream apart from the PT's
// and LT's). Three interleaved streams: number j of stream c is dimension 3 j + c, so the
// light subpath reads the same dimensions whatever the camera subpath and the
// connections use (MMLT replays them with another t).
//   stream 0, camera subpath: j = 0-1 pixel jitter, 2-3 lens point, then camera vertex
//     d >= 1 (after d segments) reads j = 4 + 4 (d - 1) + (0: BSDF lobe, 1-2: BSDF
//     direction, 3: Russian roulette);
//   stream 1, light subpath: j = 0 light choice, 1-2 point on the light, 3-4 emitted
//     direction, then light vertex d >= 1 reads j = 5 + 4 (d - 1) + (0: lobe, 1-2:
//     direction, 3: roulette);
//   stream 2, connections: s = 1 at camera vertex z_{t-1} reads j = 5 t + (0: light
//     choice, 1-2: light point); t = 1 at light vertex y_{s-1} reads j = 5 s + 3 + (0-1:
//     lens point).
enum BptStream : uint32_t { kBptCamera = 0, kBptLight = 1, kBptConnect = 2 };
constexpr uint32_t bptDim(BptStream stream, uint32_t j) { return 3 * j + uint32_t(stream); }
inline uint32_t bptCamVertexJ(int d, uint32_t m) { return 4 + 4 * uint32_t(d - 1) + m; }
inline uint32_t bptLightVertexJ(int d, uint32_t m) { return 5 + 4 * uint32_t(d - 1) + m; }
inline uint32_t bptNeeJ(int t, uint32_t m) { return 5 * uint32_t(t) + m; }
inline uint32_t bptLensJ(int s, uint32_t m) { return 5 * uint32_t(s) + 3 + m; }

// Where a batch's primary samples come from: number j of stream c of slot i. Chosen once
// per tracer (the stages are templates on it), never per number.
// BPT: hashed from the slot's key at dimension 3 j + c (the layout above); every
// strategy reads its own connection numbers.
struct HashedSamples {
    const uint64_t* key;
    float operator()(uint32_t slot, BptStream c, uint32_t j) const { return sampleDimension(key[slot], bptDim(c, j)); }
    static uint32_t connectJ(int s, int t, uint32_t m) { return s == 1 && t >= 2 ? bptNeeJ(t, m) : bptLensJ(s, m); }
};

// One strategy's primary sample vector u of a path of length k (MMLT's chains), stored
// as a row per slot: u[0] picks the strategy, then a block per stream holding its
// numbers j = 0, 1, ... in the layout above (so a change of t leaves the light
// subpath's numbers where they are), the connection's block holding the one
// connection's numbers (j = 0-2). Block sizes: the most any strategy of length k reads.
struct StrategyLayout {
    static uint32_t cameraSize(int k) { return 4 * uint32_t(k); }                            // t = k + 1
    static uint32_t lightSize(int k) { return std::max<uint32_t>(5, 4 * uint32_t(k) - 3); }  // s = k
    static constexpr uint32_t kConnectSize = 3;
    static uint32_t base(int k, BptStream c) { return c == kBptCamera ? 1 : c == kBptLight ? 1 + cameraSize(k) : 1 + cameraSize(k) + lightSize(k); }
    // Scenes with media: one more block, each walk segment's free-path number (the camera
    // walk's segment d = 1 .. t - 1 at j = d - 1, the light walk's d = 1 .. s - 1 at j = k + d - 1).
    static uint32_t mediaBase(int k) { return 1 + cameraSize(k) + lightSize(k) + kConnectSize; }
    static uint32_t mediaSize(int k) { return 2 * uint32_t(k); }
    // A spectral render: one more number, the last, the path's wavelengths (sampleWavelengths).
    static uint32_t size(int k, bool media, bool spectral = false) { return mediaBase(k) + (media ? mediaSize(k) : 0) + (spectral ? 1 : 0); }
    static uint32_t blockSize(int k, BptStream c) { return c == kBptCamera ? cameraSize(k) : c == kBptLight ? lightSize(k) : kConnectSize; }
    // The numbers strategy (s, t) reads from each block (a prefix of it).
    static uint32_t cameraUsed(int t) { return t >= 2 ? 4 * uint32_t(t) - 4 : 0; }
    static uint32_t lightUsed(int s, int t) { return s >= 2 ? 4 * uint32_t(s) - 3 : s == 1 && t == 1 ? 5 : 0; }
    static uint32_t connectUsed(int s, int t) { return (s == 1 && t >= 2) || t == 1 ? kConnectSize : 0; }
    static uint32_t cameraMediaUsed(int t) { return uint32_t(std::max(t - 1, 0)); }
    static uint32_t lightMediaUsed(int s) { return uint32_t(std::max(s - 1, 0)); }
};

struct StoredSamples {
    const float* u;  // slot i's row at u + row[i]
    const uint32_t* row;
    const uint8_t* length;  // slot i's path length k
    bool media = false;     // the rows have the media block
    float operator()(uint32_t slot, BptStream c, uint32_t j) const { return u[row[slot] + StrategyLayout::base(length[slot], c) + j]; }
    static uint32_t connectJ(int, int, uint32_t m) { return m; }
    // The free-path number of walk segment d (media block).
    float medium(uint32_t slot, BptStream c, int d) const {
        const int k = length[slot];
        return u[row[slot] + StrategyLayout::mediaBase(k) + (c == kBptCamera ? 0u : uint32_t(k)) + uint32_t(d - 1)];
    }
    // A spectral render's wavelengths' number (the row's last).
    float wavelength(uint32_t slot) const { return u[row[slot] + StrategyLayout::size(length[slot], media)]; }
};

// PSSMLT's primary sample vector (Kelemen et al. 2002 over BPT): one whole BPT sample per
// chain, every strategy of every length up to k (the walks' longest: k + 1 camera vertices,
// k light vertices). Blocks of the camera stream (StrategyLayout::cameraSize(k): the raster
// point over the whole image at j = 0-1), the light stream (lightSize(k)), the connections
// (each strategy its own numbers, as BPT's: s = 1 at z_{t-1}, t <= k, reads j = 5 t + 0-2;
// t = 1 at y_{s-1}, s <= k, j = 5 s + 3-4), with media the walks' free-path numbers
// (StrategyLayout's media block at length k) and in a spectral render the wavelengths' number.
struct WholeLayout {
    static uint32_t connectSize(int k) { return 5 * uint32_t(k) + 5; }
    static uint32_t base(int k, BptStream c) {
        return c == kBptCamera ? 0 : c == kBptLight ? StrategyLayout::cameraSize(k) : StrategyLayout::cameraSize(k) + StrategyLayout::lightSize(k);
    }
    static uint32_t mediaBase(int k) { return base(k, kBptConnect) + connectSize(k); }
    static uint32_t size(int k, bool media, bool spectral = false) {
        return mediaBase(k) + (media ? StrategyLayout::mediaSize(k) : 0) + (spectral ? 1 : 0);
    }
};

// PSSMLT's proposals, each coordinate made when it is first read (Kelemen et al.'s lazy
// mutation, as pbrt's MLTSampler): a walk that ends early reads, proposes and commits
// none of the numbers of the vertices it did not reach (a whole sample has 132 coordinates
// at MaxPathLength 10, 834 at 64, of which a Cornell box sample reads 27; proposing all
// that the scene's walks could read made a Cornell box render 1.5 times as long: docs/pssmlt.md).
// Per slot: its proposal's kind, key, and its chain's coordinates (value, lastModified at
// chainAt, the chain's last large step and the proposal's number n, mutation.h). A chain's
// coordinate never written since its seed (lastModified 0) is its seed's,
// poolCoordinate(seed, d): seeding writes nothing. A read of coordinate d: a fresh proposal
// (a large step, a pool sample) poolCoordinate(key, d); a small step smallStepOf the
// chain's coordinate; a replay the chain's coordinate itself. The value is kept in
// proposed and flagged in read (slot * dims + d), and d listed in the slot's readList
// (readCount of them), so that a second read gives the same number and the commit (and
// the next evaluation's clearing of the flags) visits exactly the coordinates read.
enum class WholeProposal : uint8_t { Replay, SmallStep, Fresh };
struct WholeSamples {
    const WholeProposal* kind;
    const uint64_t *key, *seed;               // per slot: the proposal's key, its chain's seed
    const uint32_t *chainAt, *lastLarge, *n;  // per slot
    const float* value;                       // the chains' coordinates (ChainGroup::value, lastModified)
    const uint32_t* lastModified;
    float* proposed;      // per slot and coordinate: the value read
    uint8_t* read;        // per slot and coordinate: read yet
    uint16_t* readList;   // per slot, dims of them: the coordinates read, in order
    uint16_t* readCount;  // per slot
    uint32_t dims;
    int k;  // the longest path length
    uint32_t base[3] = {WholeLayout::base(k, kBptCamera), WholeLayout::base(k, kBptLight), WholeLayout::base(k, kBptConnect)};
    uint32_t mediaBase = WholeLayout::mediaBase(k);

    float coordinate(uint32_t slot, uint32_t d) const {
        const size_t at = size_t(slot) * dims + d;
        if (read[at]) return proposed[at];
        float v;
        if (kind[slot] == WholeProposal::Fresh) {
            v = poolCoordinate(key[slot], d);
        } else {
            const size_t c = size_t(chainAt[slot]) + d;
            const uint32_t lm = lastModified[c];
            v = lm == 0 ? poolCoordinate(seed[slot], d) : value[c];
            if (kind[slot] == WholeProposal::SmallStep) v = smallStepOf(key[slot], d, v, lm, lastLarge[slot], n[slot]);
        }
        read[at] = 1;
        proposed[at] = v;
        readList[at - d + readCount[slot]++] = uint16_t(d);
        return v;
    }
    float operator()(uint32_t slot, BptStream c, uint32_t j) const { return coordinate(slot, base[c] + j); }
    static uint32_t connectJ(int s, int t, uint32_t m) { return HashedSamples::connectJ(s, t, m); }
    float medium(uint32_t slot, BptStream c, int d) const {
        return coordinate(slot, mediaBase + (c == kBptCamera ? 0u : uint32_t(k)) + uint32_t(d - 1));
    }
    // A spectral render's wavelengths' number (the whole sample's last: WholeLayout::size).
    float wavelength(uint32_t slot) const { return coordinate(slot, dims - 1); }
};

}  // namespace wmlt
