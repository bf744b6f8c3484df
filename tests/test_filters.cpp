// Pixel reconstruction filters (kernels/filter.h, docs/filters.md): the kernels against
// independent quadrature (the normalisations make every pixel's weights integrate to one,
// filter importance sampling is unbiased, the footprint visits every pixel it must), the
// formats' and the importers' parameters and bad values, and every tracer against the
// closed form of an edge seen through each filter (PT's importance-sampled camera samples
// with their signed weights, LT's, BPT's and MMLT's splats over the footprint, the film's
// edges renormalised), and PT, LT and MMLT against BPT on a lit box with negative lobes.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "kernels/filter.h"
#include "render_stats.h"
#include "scene/filter_desc.h"
#include "wavemmlt/error.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

FilterDesc named(const std::string& n) {
    FilterDesc f;
    REQUIRE(namedFilter(n, f));
    return f;
}

// Every filter kind with non-default parameters too (a box wider than a pixel takes the
// tabulated path; a Mitchell of radius 3 scales its cubic).
std::vector<std::pair<std::string, FilterDesc>> allFilters() {
    std::vector<std::pair<std::string, FilterDesc>> v;
    for (const char* n : {"box", "tent", "gaussian", "mitchell", "catmullrom", "lanczos"}) v.push_back({n, named(n)});
    FilterDesc wideBox = named("box");
    REQUIRE(setFilterParameter(wideBox, "radius", 1.25) == "");
    v.push_back({"box radius 1.25", wideBox});
    FilterDesc m3 = named("mitchell");
    REQUIRE(setFilterParameter(m3, "radius", 3) == "");
    v.push_back({"mitchell radius 3", m3});
    FilterDesc g = named("gaussian");
    REQUIRE(setFilterParameter(g, "stddev", 0.3) == "");
    v.push_back({"gaussian stddev 0.3", g});
    FilterDesc l2 = named("lanczos");
    REQUIRE(setFilterParameter(l2, "lobes", 2) == "");
    v.push_back({"lanczos 2 lobes", l2});
    return v;
}

// The message of the InputError `load` throws ("" when none).
template <class Load>
std::string errorOf(Load&& load) {
    try {
        load();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// int_a^b f by the midpoint rule on n points (independent of integrateFilter's Simpson).
double midpoint(const FilterDesc& d, double a, double b, int n = 400000) {
    double s = 0, h = (b - a) / n;
    for (int i = 0; i < n; ++i) s += double(filterValue(d, float(a + (i + 0.5) * h)));
    return s * h;
}

}  // namespace

TEST_CASE("filters: the defaults are Mitsuba 3's and the values its plugins'", "[filter]") {
    const FilterDesc g = named("gaussian");
    CHECK(g.radius == 2.0f);  // 4 stddev
    CHECK(filterValue(g, 0) == Approx(1 - std::exp(-8.0)).epsilon(1e-6));
    CHECK(filterValue(g, 2.0f) == 0);
    CHECK(named("tent").radius == 1.0f);
    CHECK(filterValue(named("tent"), 0.25f) == Approx(0.75));
    const FilterDesc m = named("mitchell");
    CHECK(filterValue(m, 0) == Approx((6 - 2 / 3.0) / 6));          // (6 - 2B) / 6
    CHECK(filterValue(m, 1.0f) == Approx(1 / 18.0).epsilon(1e-5));  // B / 6 where the cubics meet
    CHECK(filterValue(m, 1.5f) < 0);                                // the negative lobe
    const FilterDesc cr = named("catmullrom");
    CHECK(filterValue(cr, 0) == Approx(1));
    CHECK(filterValue(cr, 1.0f) == Approx(0).margin(1e-6));  // interpolating
    const FilterDesc l = named("lanczos");
    CHECK(l.radius == 3.0f);
    CHECK(filterValue(l, 1.0f) == Approx(0).margin(1e-6));
    CHECK(filterValue(l, 0.5f) == Approx(std::sin(M_PI / 2) / (M_PI / 2) * std::sin(M_PI / 6) / (M_PI / 6)).epsilon(1e-5));
    CHECK(filterValue(l, 1.5f) < 0);
    for (const auto& [name, f] : allFilters()) {
        INFO(name);
        CHECK(filterValue(f, f.radius) == 0);
        CHECK(filterValue(f, -f.radius * 1.01f) == 0);
        CHECK(filterValue(f, 0.3f) == filterValue(f, -0.3f));
    }
}

TEST_CASE("filters: integrals, normalisations and filter importance sampling against quadrature", "[filter]") {
    for (const auto& [name, d] : allFilters()) {
        INFO(name);
        const PixelFilter f = makePixelFilter(d);
        CHECK(f.box == (d.kind == FilterKind::Box && d.radius == 0.5f));
        const double exact = midpoint(d, -d.radius, d.radius);
        CHECK(f.integral == Approx(exact).epsilon(1e-6));
        // Every pixel's weights integrate to one over the film (a film 5 pixels wide: the
        // footprints of most pixels cross its edges).
        for (int n : {1, 5, 40}) {
            for (int i = 0; i < n; ++i) {
                const double c = i + 0.5, norm = filterNorm(f, i, n);
                const double inside = midpoint(d, std::max(-double(d.radius), -c), std::min(double(d.radius), n - c), 100000);
                CHECK(norm * inside == Approx(1).epsilon(1e-6));
            }
        }
        // E[g(x) f(x) / pdf(x)] = int g f for x = sampleFilter(u), u stratified.
        const int N = 1 << 20;
        double sumW = 0, sumGW = 0;
        int outside = 0;
        for (int i = 0; i < N; ++i) {
            float x;
            const double w = sampleFilter(f, (float(i) + 0.5f) / float(N), x);
            if (!(std::fabs(x) <= d.radius) || !std::isfinite(w)) ++outside;
            sumW += w;
            sumGW += w * (1 + 0.3 * x + std::cos(2.0 * x));
        }
        double gf = 0;
        const int M = 400000;
        for (int i = 0; i < M; ++i) {
            const double x = -d.radius + (i + 0.5) * 2 * d.radius / M;
            gf += (1 + 0.3 * x + std::cos(2 * x)) * double(filterValue(d, float(x))) * 2 * d.radius / M;
        }
        CHECK(outside == 0);
        CHECK(sumW / N == Approx(exact).epsilon(2e-4));
        CHECK(sumGW / N == Approx(gf).epsilon(2e-4));
    }
}

TEST_CASE("filters: the footprint visits exactly the pixels a film point has weight in", "[filter]") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(0, 1);
    for (const auto& [name, d] : allFilters()) {
        INFO(name);
        const PixelFilter f = makePixelFilter(d);
        const int W = 7, H = 5;
        std::vector<float> nx(W), ny(H);
        for (int x = 0; x < W; ++x) nx[size_t(x)] = float(filterNorm(f, x, W));
        for (int y = 0; y < H; ++y) ny[size_t(y)] = float(filterNorm(f, y, H));
        int bad = 0;
        double worst = 0;
        for (int trial = 0; trial < 2000; ++trial) {
            const float px = U(rng) * W, py = U(rng) * H;
            std::vector<float> got(size_t(W * H), 0.0f);
            int visits = 0;
            forEachFilterPixel(f, nx.data(), ny.data(), W, H, px, py, [&](uint32_t p, float w) {
                if (p < uint32_t(W * H)) got[p] += w;
                else ++bad;
                ++visits;
            });
            if (f.box) {
                if (visits != 1 || got[size_t(int(py) * W + int(px))] != 1.0f) ++bad;
                continue;
            }
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    const double want =
                        double(filterValue(d, px - (x + 0.5f)) * nx[size_t(x)]) * double(filterValue(d, py - (y + 0.5f)) * ny[size_t(y)]);
                    worst = std::max(worst, std::fabs(double(got[size_t(y * W + x)]) - want));
                }
        }
        CHECK(bad == 0);
        CHECK(worst < 1e-6);
    }
}

TEST_CASE("filters: names, parameters and their bad values", "[filter][badinput]") {
    FilterDesc f;
    CHECK_FALSE(namedFilter("sinc", f));
    CHECK(namedFilter("triangle", f));  // pbrt's name of the tent
    CHECK(f.kind == FilterKind::Tent);
    f = named("tent");
    CHECK(setFilterParameter(f, "radius", 0) == "radius must be > 0 and at most 16 pixels");
    CHECK(setFilterParameter(f, "radius", -1) != "");
    CHECK(setFilterParameter(f, "radius", 17) != "");
    CHECK(setFilterParameter(f, "radius", NAN) != "");
    CHECK(setFilterParameter(f, "stddev", 0.5) == "stddev applies to gaussian only");
    CHECK(setFilterParameter(f, "B", 0.5) == "B applies to mitchell and catmullrom only");
    f = named("gaussian");
    CHECK(setFilterParameter(f, "stddev", 0) != "");
    CHECK(setFilterParameter(f, "stddev", 0.25) == "");
    CHECK(f.radius == 1.0f);
    f = named("lanczos");
    CHECK(setFilterParameter(f, "lobes", 2.5) != "");
    CHECK(setFilterParameter(f, "lobes", 0) != "");
    CHECK(setFilterParameter(f, "wobble", 1) == "unknown filter parameter \"wobble\"");
    CHECK(describeFilter(named("catmullrom")) == "catmullrom (radius 2, B 0, C 0.5)");
}

TEST_CASE("filters: the thesis format's <Filter> and Mitsuba's rfilter", "[filter][badinput]") {
    auto thesis = [](const std::string& filter) {
        return "<Scene>\n<Settings><Width value=\"8\"/><Height value=\"8\"/>\n" + filter +
               "\n</Settings>\n<Camera Type=\"Camera\"><Position x=\"0\" y=\"0\" z=\"-5\"/><LookAt x=\"0\" y=\"0\" z=\"0\"/>"
               "<FOV value=\"45\"/></Camera>\n</Scene>\n";
    };
    CHECK(loadSceneFromString(thesis(""), "t.xml", ".").filter.kind == FilterKind::Box);
    const SceneDesc g = loadSceneFromString(thesis("<Filter name=\"gaussian\" stddev=\"0.4\"/>"), "t.xml", ".");
    CHECK(g.filter.kind == FilterKind::Gaussian);
    CHECK(g.filter.stddev == 0.4f);
    CHECK(g.filter.radius == 1.6f);
    const SceneDesc m = loadSceneFromString(thesis("<Filter name=\"mitchell\" B=\"0.2\" C=\"0.4\" radius=\"1.5\"/>"), "t.xml", ".");
    CHECK((m.filter.B == 0.2f && m.filter.C == 0.4f && m.filter.radius == 1.5f));
    auto error = [&](const std::string& filter) { return errorOf([&] { loadSceneFromString(thesis(filter), "t.xml", "."); }); };
    CHECK(error("<Filter name=\"gaussian\" radius=\"0\"/>") == "t.xml:3: Settings: Filter: radius=\"0\": radius must be > 0 and at most 16 pixels");
    CHECK(error("<Filter name=\"sinc\"/>") ==
          "t.xml:3: Settings: Filter: name=\"sinc\" is not one of box, tent, gaussian, mitchell, catmullrom, lanczos");
    CHECK(error("<Filter name=\"tent\" stddev=\"1\"/>") == "t.xml:3: Settings: Filter: stddev=\"1\": stddev applies to gaussian only");
    CHECK(error("<Filter name=\"tent\" width=\"1\"/>").find("unknown attribute \"width\"") != std::string::npos);

    auto mitsuba = [](const std::string& film) {
        return "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\n<film type=\"hdrfilm\">" + film +
               "</film>\n</sensor>\n<emitter type=\"point\"><point name=\"position\" x=\"0\" y=\"0\" z=\"0\"/></emitter></scene>\n";
    };
    auto mitsubaNoFilm = std::string(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n<emitter type=\"point\"><point "
        "name=\"position\" x=\"0\" y=\"0\" z=\"0\"/></emitter></scene>\n");
    CHECK(loadMitsubaFromString(mitsuba(""), "m.xml", ".").filter.kind == FilterKind::Gaussian);  // Mitsuba's default
    CHECK(loadMitsubaFromString(mitsubaNoFilm, "m.xml", ".").filter.kind == FilterKind::Gaussian);
    CHECK(loadMitsubaFromString(mitsuba("<rfilter type=\"box\"/>"), "m.xml", ".").filter.kind == FilterKind::Box);
    const SceneDesc t = loadMitsubaFromString(mitsuba("<rfilter type=\"tent\"><float name=\"radius\" value=\"1.5\"/></rfilter>"), "m.xml", ".");
    CHECK((t.filter.kind == FilterKind::Tent && t.filter.radius == 1.5f));
    const SceneDesc l = loadMitsubaFromString(mitsuba("<rfilter type=\"lanczos\"><integer name=\"lobes\" value=\"2\"/></rfilter>"), "m.xml", ".");
    CHECK((l.filter.kind == FilterKind::Lanczos && l.filter.radius == 2.0f && l.filter.tau == 2.0f));
    auto mError = [&](const std::string& film) { return errorOf([&] { loadMitsubaFromString(mitsuba(film), "m.xml", "."); }); };
    CHECK(mError("<rfilter type=\"tent\"><float name=\"radius\" value=\"-1\"/></rfilter>") ==
          "m.xml:3: <rfilter type=\"tent\">: radius must be > 0 and at most 16 pixels");
    CHECK(mError("<rfilter type=\"sinc\"/>") == "m.xml:3: <rfilter type=\"sinc\">: not one of box, tent, gaussian, mitchell, catmullrom, lanczos");
    CHECK(mError("<rfilter type=\"gaussian\"><float name=\"stddev\" value=\"0\"/></rfilter>") ==
          "m.xml:3: <rfilter type=\"gaussian\">: stddev must be > 0 and at most 4 pixels");
    CHECK(mError("<rfilter type=\"box\"><float name=\"width\" value=\"2\"/></rfilter>").rfind("m.xml:3:", 0) == 0);
}

namespace {

constexpr int kW = 16, kH = 12;

// A camera at the origin looking along -z at an emitter (radiance 1, facing it) that covers
// the image's left or right half exactly (x <= 0 at distance 2) and its whole height:
// length 1 only, so each pixel is the filter's share of the lit half, a closed form.
std::string edgeScene(const std::string& rfilter) {
    return "<scene version=\"3.0.0\"><integrator type=\"path\"><integer name=\"max_depth\" value=\"1\"/></integrator>"
           "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>"
           "<transform name=\"to_world\"><lookat origin=\"0, 0, 0\" target=\"0, 0, -1\" up=\"0, 1, 0\"/></transform>"
           "<film type=\"hdrfilm\"><integer name=\"width\" value=\"" +
           std::to_string(kW) + "\"/><integer name=\"height\" value=\"" + std::to_string(kH) + "\"/>" + rfilter +
           "</film></sensor>"
           "<shape type=\"rectangle\"><transform name=\"to_world\"><scale x=\"0.6\" y=\"1\"/><translate x=\"-0.6\" z=\"-2\"/></transform>"
           "<emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape></scene>";
}

// Column x's expected value: the filter's part over the lit half [a, b) of the film,
// normalised by its part over the film (independent quadrature).
double expectedColumn(const FilterDesc& d, int x, double a, double b) {
    const double c = x + 0.5, r = d.radius;
    const double lit = midpoint(d, std::max(a - c, -r), std::min(b - c, r), 20000);
    const double all = midpoint(d, std::max(-c, -r), std::min(kW - c, r), 20000);
    return std::max(0.0, std::min(b - c, r) - std::max(a - c, -r)) > 0 ? lit / all : 0.0;
}

}  // namespace

TEST_CASE("filters: every tracer renders an edge as the filter's closed form", "[filter][render]") {
    for (const char* rf :
         {"<rfilter type=\"mitchell\"/>", "<rfilter type=\"gaussian\"/>", "<rfilter type=\"lanczos\"><integer name=\"lobes\" value=\"2\"/></rfilter>",
          "<rfilter type=\"tent\"><float name=\"radius\" value=\"1.5\"/></rfilter>", "<rfilter type=\"box\"/>"}) {
        SceneDesc d = loadMitsubaFromString(edgeScene(rf), "edge.xml", ".");
        REQUIRE(d.settings.maxPathLength == 1);
        // Which half is lit: the box render's first column (exactly 0 or 1 with the box).
        SceneDesc box = d;
        box.filter = FilterDesc();
        const RenderResult b = render(box, rstats::renderOptions(TracerKind::PT, 4, 1, 1, 1));
        const bool leftLit = b.image.rgb[0] > 0.5f;
        const double a = leftLit ? 0 : kW / 2, e = leftLit ? kW / 2 : kW;
        std::vector<double> expected(kW);
        for (int x = 0; x < kW; ++x) expected[size_t(x)] = expectedColumn(d.filter, x, a, e);
        for (TracerKind t : {TracerKind::PT, TracerKind::LT, TracerKind::BPT, TracerKind::MMLT}) {
            rstats::RunStats columns;  // each column's mean over its rows, per run
            for (int k = 0; k < 12; ++k) {
                RenderOptions o = rstats::renderOptions(t, t == TracerKind::MMLT ? 64 : 16, 100 + uint64_t(k), 1, 1);
                if (t == TracerKind::MMLT) {
                    o.chains = 1024;
                    o.bootstrap = 1 << 14;
                }
                const RenderResult res = render(d, o);
                REQUIRE(res.stats.samplesNonfiniteDiscarded == 0);
                std::vector<double> col(kW, 0.0);
                for (int y = 0; y < kH; ++y)
                    for (int x = 0; x < kW; ++x) col[size_t(x)] += res.image.rgb[size_t(3 * (y * kW + x))] / kH;
                columns.add(col);
            }
            const rstats::ZTestResult z = rstats::zTest(columns, expected, 1e-4);
            INFO(rf << " " << int(t) << ": " << z.describe());
            if (z.n > 0) {
                CHECK(z.pass);
            } else {  // no column varies (the box filter's PT and MMLT): each is exact
                for (int x = 0; x < kW; ++x) CHECK(columns.mean(size_t(x)) == Approx(expected[size_t(x)]).margin(1e-6));
            }
        }
    }
}
