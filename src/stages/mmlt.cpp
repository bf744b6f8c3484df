// The MMLT driver (mmlt.md, "The algorithm"):
//  1. bootstrap: nBoot independent samples (large steps) of every length k estimate
//     b_k = E[c], c = luminance of (k + 1) times the MIS-weighted contribution;
//  2. chains are allocated to lengths in proportion to b_k by largest remainders (never
//     drawn at random), at least one per length with b_k > 0 (so --chains 1 runs one
//     chain per length), and no more chains than the mutations asked for. A length never
//     runs more chains than its bootstrap found paths with c > 0: chains seeded from the
//     same sample stay correlated for a long time (the seed room's error at equal time was
//     5x that of 1024 chains when 65536 chains shared a few hundred seeds); its chains make
//     proportionally more proposals per iteration instead (steps), so that the mutations
//     spent on each length stay in proportion to b_k;
//  3. each chain starts at a bootstrap sample of its length chosen in proportion to c
//     (systematic resampling) and replays it: the replay must give the same c bit for bit;
//  4. rounds: every chain makes the same number of proposals, batch by batch (mmlt_stages.h);
//     splats are kept per batch and added to the film in batch order after each round, so
//     a seed and any thread count give one image;
//  5. I = sum_k I_k, I_k(pixel) = b_k N_pixels (splats of length k at the pixel) / M_k with
//     M_k = chains_k x proposals per chain: each splat carries 1 / chains_k into its length's
//     film, and each film is scaled by b_k N_pixels / proposals per chain at the end. b_k
//     there is the mean c of the bootstrap and of every large step proposed (each an
//     independent uniform sample of u): so the error of b_k, which every pixel of length k
//     shares, shrinks as the render goes on instead of staying what the bootstrap left.
#include "stages/mmlt.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "kernels/distribution.h"
#include "stages/film.h"
#include "stages/mmlt_stages.h"
#include "stages/passes.h"
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

constexpr uint32_t kBatch = 1024;          // chains per batch: the wavefront's width
constexpr double kSplatsPerRound = 1 << 18;  // proposals per round (bounds splat memory, ~0.2 s)

// A batch: chains [c0, c0 + n) of group g, or bootstrap samples [c0, c0 + n) of length k.
struct Task {
    int group;
    uint32_t c0, n;
};

struct TaskOutput {
    std::vector<Splat> splats;
    MmltCounters counters;
};

// Chains per length: total * b_k / sum b by largest remainders, then at least 1 for each
// length with b_k > 0 (taken from the largest allocation while it has more than one).
std::vector<uint32_t> allocateChains(const std::vector<double>& b, uint32_t total) {
    double sum = 0;
    for (double x : b) sum += x;
    std::vector<uint32_t> n(b.size(), 0);
    std::vector<std::pair<double, size_t>> rem;
    uint32_t given = 0;
    for (size_t k = 0; k < b.size(); ++k) {
        double share = sum > 0 ? double(total) * b[k] / sum : 0;
        n[k] = uint32_t(std::floor(share));
        given += n[k];
        rem.push_back({share - std::floor(share), k});
    }
    std::stable_sort(rem.begin(), rem.end(), [](auto& a, auto& c) { return a.first > c.first; });
    for (size_t i = 0; given < total && i < rem.size(); ++i, ++given) ++n[rem[i].second];
    for (size_t k = 0; k < b.size(); ++k) {
        if (!(b[k] > 0) || n[k] > 0) continue;
        size_t big = size_t(std::max_element(n.begin(), n.end()) - n.begin());
        if (n[big] > 1) --n[big];
        n[k] = 1;
    }
    return n;
}

std::vector<Task> tasksOf(const std::vector<uint32_t>& counts) {
    std::vector<Task> t;
    for (size_t g = 0; g < counts.size(); ++g)
        for (uint32_t c0 = 0; c0 < counts[g]; c0 += kBatch) t.push_back({int(g), c0, std::min(kBatch, counts[g] - c0)});
    return t;
}

double physicalMemory() {
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? double(pages) * double(size) : 0;
}

}  // namespace

uint64_t mmltChainBytes(int k) { return uint64_t(StrategyLayout::size(k)) * 8 + 4 * 4 + 12; }

RenderResult renderMmlt(const Scene& scene, const RenderOptions& opt) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
    const int kMin = std::max(1, opt.minPathLength), kMax = opt.maxPathLength;
    const int nLengths = kMax - kMin + 1;
    const double pixels = double(scene.camera.width) * double(scene.camera.height);
    const double targetMutations = double(opt.spp) * pixels;
    const uint32_t nBoot = opt.bootstrap > 0
                               ? uint32_t(opt.bootstrap)
                               : uint32_t(std::clamp(0.05 * targetMutations / nLengths, 4096.0, double(1 << 20)));
    tbb::enumerable_thread_specific<MmltBatch> batches([&] {
        MmltBatch mb;
        mb.reserve(kBatch, kMax);
        return mb;
    });
    tbb::enumerable_thread_specific<PtCounters> rays;
    RenderResult res;
    RenderStats::Mmlt& ms = res.stats.mmlt;
    ms.b.assign(kMax + 1, 0.0);
    ms.chains.assign(kMax + 1, 0);
    ms.proposedSmall.assign(kMax + 1, 0);
    ms.acceptedSmall = ms.proposedLarge = ms.acceptedLarge = ms.proposedSmall;
    ms.bootstrapSamples = nBoot;
    uint64_t discarded = 0;

    // 1. Bootstrap.
    std::vector<std::vector<float>> bootC(size_t(kMax + 1));
    std::vector<uint32_t> bootCounts(size_t(kMax + 1), 0);
    for (int k = kMin; k <= kMax; ++k) {
        bootC[size_t(k)].assign(nBoot, 0.0f);
        bootCounts[size_t(k)] = nBoot;
    }
    {
        const std::vector<Task> tasks = tasksOf(bootCounts);
        std::vector<uint64_t> nonfinite(tasks.size(), 0);
        tbb::parallel_for(size_t(0), tasks.size(), [&](size_t ti) {
            const Task& t = tasks[ti];
            MmltBatch& mb = batches.local();
            mb.counters = MmltCounters();
            fillBootstrapRows(mb, t.group, t.c0, t.n, opt.seed);
            evaluateProposals(scene, mb, opt.misBeta, rays.local());
            for (uint32_t i = 0; i < t.n; ++i) {
                const Vec3 F = contributionOf(mb, i);
                float c = luminance(F);
                if (!std::isfinite(c) || !isFinite(F)) {
                    ++mb.counters.nonfinite;
                    c = 0;
                }
                bootC[size_t(t.group)][t.c0 + i] = c;
            }
            nonfinite[ti] = mb.counters.nonfinite;
        });
        for (uint64_t n : nonfinite) discarded += n;
    }
    double bSum = 0;
    std::vector<double> cSum(size_t(kMax + 1), 0.0);  // sum of c over bootstrap and large steps
    std::vector<uint64_t> cCount(size_t(kMax + 1), 0);
    for (int k = kMin; k <= kMax; ++k) {
        for (float c : bootC[size_t(k)]) cSum[size_t(k)] += c;
        cCount[size_t(k)] = nBoot;
        ms.b[size_t(k)] = cSum[size_t(k)] / nBoot;
        bSum += ms.b[size_t(k)];
    }
    ms.bBootstrap = ms.b;
    if (!(bSum > 0))
        throw InputError("no light reaches the camera: the bootstrap's " + std::to_string(nBoot) +
                         " samples of each path length " + std::to_string(kMin) + ".." + std::to_string(kMax) +
                         " all carry zero radiance (check the lights, MinPathLength and MaxPathLength)");

    // 2. Chains per length.
    const int positive = int(std::count_if(ms.b.begin(), ms.b.end(), [](double x) { return x > 0; }));
    // No more chains than mutations asked for (a small image at few mutations per pixel).
    const double asked = opt.timeBudget > 0 ? double(opt.chains) : std::min(double(opt.chains), targetMutations);
    const uint32_t total = std::max<uint32_t>(uint32_t(std::max(asked, 1.0)), uint32_t(positive));
    const std::vector<uint32_t> allocated = allocateChains(ms.b, total);
    std::vector<uint32_t> chainCounts(allocated.size(), 0), steps(allocated.size(), 1);
    ms.bootstrapNonzero.assign(allocated.size(), 0);
    for (int k = kMin; k <= kMax; ++k) {
        const uint32_t seeds = uint32_t(std::count_if(bootC[size_t(k)].begin(), bootC[size_t(k)].end(),
                                                      [](float c) { return c > 0; }));
        ms.bootstrapNonzero[size_t(k)] = seeds;
        chainCounts[size_t(k)] = std::min(allocated[size_t(k)], seeds);
        if (chainCounts[size_t(k)])
            steps[size_t(k)] = std::max<uint32_t>(
                1, uint32_t(std::lround(double(allocated[size_t(k)]) / double(chainCounts[size_t(k)]))));
    }
    ms.chainsAllocated = allocated;
    double bytes = 0;
    for (int k = kMin; k <= kMax; ++k) bytes += double(chainCounts[size_t(k)]) * double(mmltChainBytes(k));
    const double mem = physicalMemory();
    if (mem > 0 && bytes > 0.75 * mem)
        throw InputError("--chains " + std::to_string(total) + " would need " + std::to_string(uint64_t(bytes) >> 20) +
                         " MiB of chain state, more than this machine's memory allows");
    ms.chainBytes = uint64_t(bytes);

    // 3. Seed each chain from the bootstrap in proportion to c, and replay it.
    std::vector<ChainGroup> groups(size_t(kMax + 1));
    uint32_t first = 0;
    std::vector<std::vector<uint32_t>> seedIndex(size_t(kMax + 1));
    for (int k = kMin; k <= kMax; ++k) {
        ChainGroup& g = groups[size_t(k)];
        g.k = k;
        g.count = chainCounts[size_t(k)];
        g.steps = steps[size_t(k)];
        g.first = first;
        first += g.count;
        g.dims = StrategyLayout::size(k);
        g.b = ms.b[size_t(k)];
        ms.chains[size_t(k)] = g.count;
        if (g.count == 0) continue;
        g.value.resize(size_t(g.dims) * g.count);
        g.lastModified.assign(g.value.size(), 0);
        g.accepted.assign(g.count, 0);
        g.lastLarge.assign(g.count, 0);
        g.F.assign(g.count, Vec3(0.0f));
        g.c.assign(g.count, 0.0f);
        g.pixel.assign(g.count, 0);
        Distribution1D pick(bootC[size_t(k)]);
        const float offset = sampleDimension(mmltBootstrapKey(opt.seed, k, 0xffffffffu), 0);
        seedIndex[size_t(k)].resize(g.count);
        for (uint32_t c = 0; c < g.count; ++c) {
            float pmf;
            const uint32_t idx = uint32_t(pick.sampleDiscrete((float(c) + offset) / float(g.count), &pmf));
            seedIndex[size_t(k)][c] = idx;
            const uint64_t key = mmltBootstrapKey(opt.seed, k, idx);
            for (uint32_t d = 0; d < g.dims; ++d) g.value[size_t(d) * g.count + c] = sampleDimension(key, d);
        }
    }
    const std::vector<Task> tasks = tasksOf(chainCounts);
    {
        std::vector<uint64_t> mismatches(tasks.size(), 0);
        tbb::parallel_for(size_t(0), tasks.size(), [&](size_t ti) {
            const Task& t = tasks[ti];
            ChainGroup& g = groups[size_t(t.group)];
            MmltBatch& mb = batches.local();
            fillCurrentRows(g, mb, t.c0, t.n);
            evaluateProposals(scene, mb, opt.misBeta, rays.local());
            for (uint32_t i = 0; i < t.n; ++i) {
                const uint32_t c = t.c0 + i;
                const Vec3 F = contributionOf(mb, i);
                const float cc = luminance(F);
                const float expected = bootC[size_t(t.group)][seedIndex[size_t(t.group)][c]];
                if (std::memcmp(&cc, &expected, sizeof cc) != 0) ++mismatches[ti];
                g.F[c] = F;
                g.c[c] = cc;
                g.pixel[c] = mb.bpt.pixel[i];
            }
        });
        for (uint64_t n : mismatches) ms.replayMismatches += n;
    }

    // 4. Rounds of proposals.
    double perIterationProposals = 0;  // every chain of length k makes steps_k proposals
    for (const ChainGroup& g : groups) perIterationProposals += double(g.count) * g.steps;
    const uint64_t target = std::max<uint64_t>(1, uint64_t(std::ceil(targetMutations / perIterationProposals)));
    const uint32_t perRound = uint32_t(std::clamp(kSplatsPerRound / perIterationProposals, 1.0, 4096.0));
    std::vector<SplatFilm> films;  // one per length with chains (index: group)
    for (int k = 0; k <= kMax; ++k)
        films.emplace_back(groups[size_t(k)].count ? scene.camera.width : 0, groups[size_t(k)].count ? scene.camera.height : 0);
    std::vector<TaskOutput> outputs(tasks.size());
    uint64_t iteration = 0;
    bool stopped = false;
    double perIteration = 0;  // seconds per proposal of every chain, measured
    const bool timed = opt.timeBudget > 0;
    while (true) {
        if (!timed && iteration >= target) break;
        if (opt.cancel && opt.cancel->load()) { stopped = true; break; }
        uint32_t r = timed ? perRound : uint32_t(std::min<uint64_t>(perRound, target - iteration));
        if (timed) {  // a time budget: the last rounds shrink so as to end on time
            const double left = opt.timeBudget - elapsed();
            if (left <= 0.5 * perIteration) break;
            r = perIteration > 0 ? uint32_t(std::clamp(std::floor(left / perIteration + 0.5), 1.0, double(r)))
                                 : 1;  // the first round measures
        }
        const double roundStart = elapsed();
        tbb::parallel_for(size_t(0), tasks.size(), [&](size_t ti) {
            const Task& t = tasks[ti];
            ChainGroup& g = groups[size_t(t.group)];
            MmltBatch& mb = batches.local();
            mb.splats.clear();
            mb.counters = MmltCounters();
            const float scale = float(1.0 / double(g.count));
            for (uint64_t n = iteration * g.steps; n < (iteration + r) * g.steps; ++n) {
                mutateChains(g, mb, t.c0, t.n, opt.seed, uint32_t(n), opt.probLarge);
                evaluateProposals(scene, mb, opt.misBeta, rays.local());
                acceptAndSplat(g, mb, opt.seed, uint32_t(n), scale);
            }
            outputs[ti].splats.swap(mb.splats);
            outputs[ti].counters = mb.counters;
        });
        for (size_t ti = 0; ti < tasks.size(); ++ti) {  // in batch order: deterministic
            const size_t k = size_t(groups[size_t(tasks[ti].group)].k);
            for (const Splat& s : outputs[ti].splats) films[k].add(s);
            const MmltCounters& c = outputs[ti].counters;
            cSum[k] += c.largeSum;
            cCount[k] += c.proposed[1];
            ms.proposedSmall[k] += c.proposed[0];
            ms.acceptedSmall[k] += c.accepted[0];
            ms.proposedLarge[k] += c.proposed[1];
            ms.acceptedLarge[k] += c.accepted[1];
            discarded += c.nonfinite;
        }
        iteration += r;
        perIteration = (elapsed() - roundStart) / r;
        if (opt.progress)
            opt.progress(timed ? std::min(1.0, elapsed() / opt.timeBudget) : double(iteration) / double(target));
    }

    // 5. The image.
    PassResult pr;
    pr.seconds = elapsed();
    pr.completedSpp = uint32_t(double(iteration) * perIterationProposals / pixels);
    pr.stopped = stopped;
    RenderStats::Mmlt keep = ms;
    res = startResult("mmlt", scene, opt, pr, rays);
    res.stats.mmlt = keep;
    res.stats.mmlt.iterations = iteration;
    res.stats.mmlt.mutations = uint64_t(double(iteration) * perIterationProposals);
    res.stats.mmlt.proposalsPerChain.assign(size_t(kMax + 1), 0);
    for (const ChainGroup& g : groups) res.stats.mmlt.proposalsPerChain[size_t(g.k)] = g.count ? iteration * g.steps : 0;
    res.stats.samplesNonfiniteDiscarded = discarded;
    res.image = Image(scene.camera.width, scene.camera.height);
    std::vector<double> sum(res.image.rgb.size(), 0.0);
    if (opt.lengthImages) res.lengthImages.assign(size_t(kMax) + 1, Image(scene.camera.width, scene.camera.height));
    for (int k = kMin; k <= kMax; ++k) {
        const double b = cSum[size_t(k)] / double(cCount[size_t(k)]);
        res.stats.mmlt.b[size_t(k)] = b;
        if (!groups[size_t(k)].count || iteration == 0) continue;
        const double norm = b * pixels / double(iteration * groups[size_t(k)].steps);
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += films[size_t(k)].sum[i] * norm;
        if (opt.lengthImages)
            for (size_t i = 0; i < sum.size(); ++i) res.lengthImages[size_t(k)].rgb[i] = float(films[size_t(k)].sum[i] * norm);
    }
    for (size_t i = 0; i < sum.size(); ++i) res.image.rgb[i] = float(sum[i]);
    res.stats.lengthMeanLuminance = res.stats.mmlt.b;
    return res;
}

}  // namespace wmlt
