// The --stats JSON (stats_json.h): one object, MMLT's and PSSMLT's figures under their own
// prefixes, the ranks' exchanges when split across processes.
#include "app/stats_json.h"

#include <iomanip>
#include <sstream>

namespace wmlt {

namespace {

// MMLT's figures, each an object keyed by path length where it is per length. PSSMLT's the
// same under its own prefix, with one value where MMLT's are per length (its one chain
// group, index 0, holds every length).
void writeMmltStats(std::ostream& o, const RenderStats& st, const Settings& s) {
    const RenderStats::Mmlt& m = st.mmlt;
    const bool whole = st.tracer == "pssmlt";
    const std::string prefix = whole ? "pssmlt_" : "mmlt_";
    auto perLength = [&](const char* name, auto value) {
        o << ",\n  \"" << prefix << (name + 5) << "\": ";  // name without "mmlt_"
        if (whole) {
            o << value(size_t(0));
            return;
        }
        o << "{";
        for (int k = s.minPathLength; k <= s.maxPathLength && k < int(m.b.size()); ++k)
            o << (k == s.minPathLength ? "" : ", ") << '"' << k << "\": " << value(size_t(k));
        o << "}";
    };
    auto rate = [](uint64_t a, uint64_t p) { return p ? double(a) / double(p) : 0.0; };
    perLength("mmlt_b", [&](size_t k) { return m.b[k]; });
    perLength("mmlt_b_bootstrap", [&](size_t k) { return m.bBootstrap[k]; });
    perLength("mmlt_chains", [&](size_t k) { return m.chains[k]; });
    perLength("mmlt_chains_seeded", [&](size_t k) { return m.chainsSeeded[k]; });
    perLength("mmlt_distinct_seeds", [&](size_t k) { return m.distinctSeeds[k]; });
    perLength("mmlt_bootstrap_samples", [&](size_t k) { return m.bootstrapSamples[k]; });
    perLength("mmlt_bootstrap_with_light", [&](size_t k) { return m.bootstrapNonzero[k]; });
    perLength("mmlt_pool_samples", [&](size_t k) { return m.poolSamples[k]; });
    perLength("mmlt_proposals", [&](size_t k) { return m.proposals[k]; });
    perLength("mmlt_acceptance_small", [&](size_t k) { return rate(m.acceptedSmall[k], m.proposedSmall[k]); });
    perLength("mmlt_acceptance_large", [&](size_t k) { return rate(m.acceptedLarge[k], m.proposedLarge[k]); });
    if (m.learnedSteps) perLength("mmlt_small_step_sigma", [&](size_t k) { return m.smallStepSigma[k]; });
    if (m.filmSteps != FilmSteps::Off) {
        perLength("mmlt_film_step_share", [&](size_t k) { return m.filmStepShare[k]; });
        perLength("mmlt_film_steps_proposed", [&](size_t k) { return m.proposedFilm[k]; });
        perLength("mmlt_acceptance_film", [&](size_t k) { return rate(m.acceptedFilm[k], m.proposedFilm[k]); });
    }
    if (m.delayedRejection) {
        perLength("mmlt_delayed_proposals", [&](size_t k) { return m.proposedDelayed[k]; });
        perLength("mmlt_acceptance_delayed", [&](size_t k) { return rate(m.acceptedDelayed[k], m.proposedDelayed[k]); });
    }
    uint64_t acc[3], prop[3];
    m.stepTotals(acc, prop);
    o << ",\n  \"" << prefix << "acceptance\": {\"small\": " << rate(acc[0], prop[0]) << ", \"large\": " << rate(acc[1], prop[1]);
    if (prop[2]) o << ", \"film\": " << rate(acc[2], prop[2]);
    o << ", \"all\": " << rate(acc[0] + acc[1] + acc[2], prop[0] + prop[1] + prop[2]) << "}"
      << ",\n  \"" << prefix << "mutations\": " << m.mutations << ",\n  \"" << prefix
      << "mutations_per_second\": " << (st.seconds > 0 ? double(m.mutations) / st.seconds : 0.0) << ",\n  \"" << prefix
      << "iterations\": " << m.iterations << ",\n  \"" << prefix << "passes\": " << m.passes << ",\n  \"" << prefix
      << "pass_length\": " << m.passLength << ",\n  \"" << prefix << "renewals\": " << (m.passes > 0 ? m.passes - 1 : 0) << ",\n  \"" << prefix
      << "tasks_per_round\": " << m.tasksPerRound << ",\n  \"" << prefix << "longest_task_ratio\": " << m.longestTaskRatio << ",\n  \"" << prefix
      << "replay_mismatches\": " << m.replayMismatches << ",\n  \"" << prefix << "chain_state_bytes\": " << m.chainBytes << ",\n  \"" << prefix
      << "chains_asked\": " << (m.chainsAuto ? std::string("\"auto\"") : std::to_string(m.chainsAsked)) << ",\n  \"" << prefix
      << "chains_run\": " << m.chainsRun << ",\n  \"" << prefix << "chains_reason\": \"" << m.chainsReason << "\"";
    o << ",\n  \"" << prefix << "target\": \"" << mmltTargetName(m.target) << "\"";
    o << ",\n  \"" << prefix << "target_exponent\": " << m.targetExponent;
    o << ",\n  \"" << prefix << "delayed_rejection\": " << (m.delayedRejection ? "true" : "false");
    o << ",\n  \"" << prefix << "film_steps\": \"" << filmStepsName(m.filmSteps) << "\"";
    if (m.target == MmltTarget::Relative)
        o << ",\n  \"" << prefix << "target_maps\": " << m.targetMaps << ",\n  \"" << prefix << "target_tile_size\": " << m.targetTileSize
          << ",\n  \"" << prefix << "target_scale\": {\"least\": " << m.targetScaleLeast << ", \"most\": " << m.targetScaleMost << "}";
    if (!m.poolDigestByRank.empty()) o << ",\n  \"" << prefix << "pool_digest\": \"" << std::hex << m.poolDigestByRank[0] << std::dec << "\"";
    if (st.ranks.count > 1) {  // what each rank computed: the same on every rank (docs/mpi.md)
        o << ",\n  \"" << prefix << "b_by_rank\": [";
        for (size_t r = 0; r < m.bByRank.size(); ++r) {
            if (whole) {
                o << (r ? ", " : "") << std::setprecision(17) << m.bByRank[r][0];
                continue;
            }
            o << (r ? ", " : "") << "{";
            for (int k = s.minPathLength; k <= s.maxPathLength && k < int(m.bByRank[r].size()); ++k)
                o << (k == s.minPathLength ? "" : ", ") << '"' << k << "\": " << std::setprecision(17) << m.bByRank[r][size_t(k)];
            o << "}";
        }
        o << std::setprecision(9) << "],\n  \"" << prefix << "pool_digest_by_rank\": [";
        for (size_t r = 0; r < m.poolDigestByRank.size(); ++r) o << (r ? ", " : "") << '"' << std::hex << m.poolDigestByRank[r] << std::dec << '"';
        o << "]";
    }
}

// The ranks of a render split across processes: their count always, the exchanges' cost
// (per rank) when there are several.
void writeRankStats(std::ostream& o, const RenderStats& st) {
    o << ",\n  \"ranks\": " << st.ranks.count;
    if (st.ranks.count <= 1) return;
    uint64_t bytes = 0;
    double seconds = 0;
    o << ",\n  \"mpi_bytes_by_rank\": [";
    for (size_t r = 0; r < st.ranks.bytes.size(); ++r) {
        o << (r ? ", " : "") << st.ranks.bytes[r];
        bytes += st.ranks.bytes[r];
    }
    o << "],\n  \"mpi_seconds_by_rank\": [";
    for (size_t r = 0; r < st.ranks.seconds.size(); ++r) {
        o << (r ? ", " : "") << st.ranks.seconds[r];
        seconds = std::max(seconds, st.ranks.seconds[r]);
    }
    o << "],\n  \"mpi_bytes\": " << bytes << ",\n  \"mpi_seconds_max\": " << seconds << ",\n  \"mpi_exchanges\": " << st.ranks.exchanges
      << ",\n  \"mpi_boundaries\": " << st.ranks.boundaries
      << ",\n  \"mpi_bytes_per_boundary\": " << (st.ranks.boundaries ? double(bytes) / double(st.ranks.boundaries) : 0.0)
      << ",\n  \"mpi_seconds_per_boundary\": " << (st.ranks.boundaries ? seconds / double(st.ranks.boundaries) : 0.0);
}

}  // namespace

std::string statsJson(const RenderResult& r, const Settings& s) {
    std::ostringstream o;
    o.precision(9);
    const RenderStats& st = r.stats;
    o << "{\n  \"tracer\": \"" << st.tracer << "\",\n  \"seconds\": " << st.seconds << ",\n  \"threads\": " << st.threads
      << ",\n  \"spp\": " << st.spp << ",\n  \"width\": " << s.width << ",\n  \"height\": " << s.height
      << ",\n  \"rays_intersect\": " << st.raysIntersect << ",\n  \"rays_occluded\": " << st.raysOccluded
      << ",\n  \"mrays_per_second\": " << st.mraysPerSecond() << ",\n  \"samples_nonfinite_discarded\": " << st.samplesNonfiniteDiscarded
      << ",\n  \"cancelled\": " << (st.cancelled ? "true" : "false") << ",\n  \"spectral\": " << (st.spectral ? "true" : "false")
      << ",\n  \"spectral_reason\": \"" << st.spectralReason << "\"";
    if (st.misBeta > 0) o << ",\n  \"mis_beta\": " << st.misBeta;
    o << ",\n  \"mean_luminance_by_length\": {";
    // Path length k (segments) -> the image's mean luminance carried by length-k paths.
    for (int k = s.minPathLength; k <= s.maxPathLength && k < int(st.lengthMeanLuminance.size()); ++k)
        o << (k == s.minPathLength ? "" : ", ") << '"' << k << "\": " << st.lengthMeanLuminance[k];
    o << "}";
    writeRankStats(o, st);
    if (st.tracer == "mmlt" || st.tracer == "pssmlt") writeMmltStats(o, st, s);
    o << ",\n  \"buffers_bytes\": {";
    for (size_t i = 0; i < st.buffers.size(); ++i) o << (i ? ", " : "") << '"' << st.buffers[i].first << "\": " << st.buffers[i].second;
    o << "}";
    o << ",\n  \"scene_features\": " << r.featuresJson << "\n}\n";
    return o.str();
}

}  // namespace wmlt
