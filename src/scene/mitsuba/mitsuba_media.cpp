// Mitsuba 3's participating media (docs/mitsuba.md, docs/media.md): `homogeneous` (sigma_t,
// albedo, scale) with an `isotropic` or `hg` phase, referenced as a shape's `interior` and
// `exterior` and as the sensor's medium; the `null` BSDF makes a shape an index-matched
// boundary (ShapeDesc::passThrough).
#include <cmath>
#include <cstring>

#include "scene/mitsuba/mitsuba_importer.h"
#include "scene/read_file.h"
#include "wavemmlt/error.h"

namespace wmlt::mitsuba {

namespace {

// A Mitsuba .vol grid (version 3, float32): "VOL", 3, encoding 1, x, y, z resolutions, the
// channels, a bounding box (6 floats), then the values, x fastest, channels innermost.
struct VolFile {
    int nx = 0, ny = 0, nz = 0, channels = 0;
    float bbox[6] = {0, 0, 0, 1, 1, 1};
    std::vector<float> values;
};
VolFile readVol(const std::string& path) {
    const std::string data = readWholeFile(path, "grid volume");
    auto fail = [&](const std::string& msg) { throw InputError(path, 0, msg); };
    if (data.size() < 48 || data.compare(0, 3, "VOL") != 0) fail("not a Mitsuba .vol file (no \"VOL\" header)");
    if (data[3] != 3) fail("a .vol file of version " + std::to_string(int(data[3])) + " (version 3 is read)");
    int32_t head[5];
    std::memcpy(head, data.data() + 4, sizeof head);
    if (head[0] != 1) fail("a .vol file with encoding " + std::to_string(head[0]) + " (float32, 1, is read)");
    VolFile v;
    v.nx = head[1], v.ny = head[2], v.nz = head[3], v.channels = head[4];
    if (v.nx < 1 || v.ny < 1 || v.nz < 1 || v.channels < 1 || double(v.nx) * v.ny * v.nz * v.channels > 2e9)
        fail("a .vol file with a bad size " + std::to_string(v.nx) + " x " + std::to_string(v.ny) + " x " + std::to_string(v.nz) + " x " +
             std::to_string(v.channels));
    std::memcpy(v.bbox, data.data() + 24, sizeof v.bbox);
    const size_t n = size_t(v.nx) * size_t(v.ny) * size_t(v.nz) * size_t(v.channels);
    if (data.size() - 48 < n * 4) fail("the .vol file is truncated: " + std::to_string((data.size() - 48) / 4) + " values for " + std::to_string(n));
    v.values.resize(n);
    std::memcpy(v.values.data(), data.data() + 48, n * 4);
    return v;
}

// Two grid transforms equal up to float rounding.
bool sameAffine(const Affine& a, const Affine& b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            if (std::fabs(a.m[r][c] - b.m[r][c]) > 1e-5f * (1 + std::fabs(a.m[r][c]))) return false;
    return true;
}

}  // namespace

int Importer::medium(Node n) {
    auto it = mediumOf_.find(n.internal_object());
    if (it != mediumOf_.end()) return it->second;
    Props p = props(n);
    if (p.type() != "homogeneous" && p.type() != "heterogeneous")
        p.fail(n, "medium \"" + p.type() + "\" is not supported (homogeneous and heterogeneous are; docs/mitsuba.md)");
    MediumDesc m;
    m.name = n.attribute("id").value();
    m.line = files_.line(n);
    // Mitsuba 3: sigma_s = albedo sigma_t, sigma_a = sigma_t - sigma_s, both times scale;
    // heterogeneous: sigma_t a one-channel gridvolume (its values the density) or a
    // constvolume, albedo a constant, a constvolume or a gridvolume (one or three channels)
    // on the same grid as sigma_t's (or, with sigma_t constant, its own)
    struct Grid {
        VolFile vol;
        Affine worldToGrid;
        Node at;
    };
    auto readGrid = [&](Node v, Props& vp) {
        Grid g{[&] {
                   try {
                       return readVol(resolve(vp.getString("filename", "")));
                   } catch (const InputError& e) {
                       vp.fail(v, e.what());
                   }
               }(),
               Affine(), v};
        if (vp.getString("wrap_mode", "clamp") != "clamp") vp.fail(v, "wrap_mode other than clamp is not supported");
        vp.getString("filter_type", "trilinear");
        vp.getBool("raw", false);
        Matrix M = vp.getTransform("to_world");
        if (M.det3() == 0) vp.fail(v, "to_world is singular");
        if (vp.getBool("use_grid_bbox", false)) {  // the file's box, in the volume's space
            const float* b = g.vol.bbox;
            if (!(b[3] > b[0] && b[4] > b[1] && b[5] > b[2])) vp.fail(v, "use_grid_bbox: the file's box is empty");
            M = M * Matrix::translate(b[0], b[1], b[2]) * Matrix::scale(b[3] - b[0], b[4] - b[1], b[5] - b[2]);
        }
        g.worldToGrid = M.inverse().affine();
        return g;
    };
    std::vector<Grid> sigmaGrid, albedoGrid;  // at most one each
    auto constant = [&](const char* name, Vec3 def, Props::ColorUse use, std::vector<Grid>* grid) {
        if (!p.isNested("volume", name)) return p.getColor(name, def, use);
        const Node v = p.getNested("volume", name);
        Props vp = props(v);
        Vec3 c(1.0f);
        if (vp.type() == "constvolume") {
            c = vp.getColor("value", Vec3(1.0f), use);
        } else if (vp.type() == "gridvolume" && grid) {
            grid->push_back(readGrid(v, vp));
        } else {
            vp.fail(v, "volume \"" + vp.type() + "\" is not supported here (" + (grid ? "gridvolume, " : "") + "constvolume)");
        }
        vp.finish();
        return c;
    };
    const bool heterogeneous = p.type() == "heterogeneous";
    const Vec3 sigmaT = constant("sigma_t", Vec3(1.0f), Props::ColorUse::Unbounded, heterogeneous ? &sigmaGrid : nullptr);
    const Vec3 albedo = constant("albedo", Vec3(0.75f), Props::ColorUse::Reflectance, heterogeneous ? &albedoGrid : nullptr);
    if (!sigmaGrid.empty()) {
        const Grid& g = sigmaGrid[0];
        if (g.vol.channels != 1) p.fail(g.at, "a sigma_t grid of " + std::to_string(g.vol.channels) + " channels (one is supported)");
        m.nx = g.vol.nx, m.ny = g.vol.ny, m.nz = g.vol.nz;
        m.density = g.vol.values;
        m.worldToGrid = g.worldToGrid;
        m.clampEdges = true;
    }
    if (!albedoGrid.empty()) {
        const Grid& g = albedoGrid[0];
        if (g.vol.channels != 1 && g.vol.channels != 3)
            p.fail(g.at, "an albedo grid of " + std::to_string(g.vol.channels) + " channels (one or three are supported)");
        if (sigmaGrid.empty()) {  // a constant sigma_t: a density of ones on the albedo's grid
            m.nx = g.vol.nx, m.ny = g.vol.ny, m.nz = g.vol.nz;
            m.density.assign(size_t(m.nx) * size_t(m.ny) * size_t(m.nz), 1.0f);
            m.worldToGrid = g.worldToGrid;
            m.clampEdges = true;
        } else if (g.vol.nx != m.nx || g.vol.ny != m.ny || g.vol.nz != m.nz || !sameAffine(g.worldToGrid, m.worldToGrid)) {
            p.fail(g.at, "an albedo grid on another grid than sigma_t's (the same size and to_world are supported)");
        }
        const size_t n = m.density.size();
        for (size_t i = 0; i < n; ++i) {
            const float* a = &g.vol.values[i * size_t(g.vol.channels)];
            m.albedoGrid.push_back(g.vol.channels == 3 ? Vec3(a[0], a[1], a[2]) : Vec3(a[0]));
            for (int c = 0; c < 3; ++c)
                if (!(m.albedoGrid.back()[c] >= 0 && m.albedoGrid.back()[c] <= 1)) p.fail(g.at, "albedo grid values must be in [0, 1]");
        }
    }
    const float scale = p.getFloat("scale", 1.0f);
    p.getBool("sample_emitted", true);
    m.albedo = albedo;
    m.sigmaS = albedo * sigmaT * scale;
    m.sigmaA = (sigmaT * scale) - m.sigmaS;
    for (Node ph : p.nested("phase")) {
        Props pp = props(ph);
        if (pp.type() == "hg") m.g = pp.getFloat("g", 0.8f);
        else if (pp.type() != "isotropic") pp.fail(ph, "phase \"" + pp.type() + "\" is not supported (isotropic and hg are)");
        pp.finish();
    }
    p.finish();
    auto bad = [](Vec3 v) { return !isFinite(v) || v.x < 0 || v.y < 0 || v.z < 0; };
    if (bad(m.sigmaA) || bad(m.sigmaS)) p.fail(n, "sigma_t (times scale) must be finite and >= 0, albedo in [0, 1]");
    if (!(m.g > -1 && m.g < 1)) p.fail(n, "the phase function's g must be in (-1, 1)");
    const int index = int(s_.media.size());
    s_.media.push_back(m);
    mediumOf_[n.internal_object()] = index;
    return index;
}

void Importer::shapeMedia(Props& p, ShapeDesc& sh) {
    const Node in = p.getNested("medium", "interior"), out = p.getNested("medium", "exterior");
    if (!in && !out) return;
    sh.mediumBoundary = true;
    sh.mediumInside = in ? medium(in) : -1;
    sh.mediumOutside = out ? medium(out) : -1;
}

}  // namespace wmlt::mitsuba
