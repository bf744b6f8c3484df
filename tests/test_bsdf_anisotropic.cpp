// Anisotropic microfacet distributions (microfacet.h, alphaX != alphaY) and the materials
// over them: D's projected area and the visible normals' pdf integrate to 1, sampling
// matches the pdfs (chi-square), the conductor is reciprocal and loses energy only; the
// isotropic case computes what b069d67 (before anisotropy) computed, bit for bit; the
// importer's alpha_u / alpha_v; the shading frame's x along dp/du.
#include <catch2/catch.hpp>

#include <cstring>

#include "chi2.h"
#include "kernels/bsdf.h"
#include "scene/scene.h"
#include "stages/core/surface.h"
#include "wavemmlt/error.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;
using chi2::close;
using chi2::dirAt;

namespace {
constexpr double kMinP = 1e-3;

const char* typeName(MicrofacetType t) { return t == MicrofacetType::GGX ? "ggx" : "beckmann"; }

// (alphaX, alphaY) pairs: strong anisotropy both ways round, and moderate.
std::vector<Microfacet> anisoCases() {
    std::vector<Microfacet> v;
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX}) {
        v.emplace_back(t, 0.05f, 0.5f);
        v.emplace_back(t, 0.5f, 0.05f);
        v.emplace_back(t, 0.3f, 0.12f);
    }
    return v;
}

// b069d67's isotropic D, Lambda and GGX sampling, as they were: the oracle of the
// bit-identity test (the Beckmann sampler's arithmetic is shared, so it has none here).
float oldD(MicrofacetType type, float alpha, Vec3 m) {
    if (!(m.z > 0)) return 0.0f;
    const double c2 = double(m.z) * m.z, a2 = double(alpha) * alpha;
    const double s2 = std::max(0.0, double(m.x) * m.x + double(m.y) * m.y);
    const double tan2 = s2 / c2, c4 = c2 * c2;
    if (type == MicrofacetType::Beckmann) return float(std::exp(-tan2 / a2) / (M_PI * a2 * c4));
    const double k = 1.0 + tan2 / a2;
    return float(1.0 / (M_PI * a2 * c4 * k * k));
}
double oldLambda(MicrofacetType type, float alphaF, Vec3 w) {
    const double s2 = std::max(0.0, double(w.x) * w.x + double(w.y) * w.y), c = std::fabs(double(w.z));
    if (s2 == 0) return 0.0;
    if (c == 0) return INFINITY;
    const double alpha = alphaF;
    if (type == MicrofacetType::GGX) {
        const double t2 = alpha * alpha * s2 / (c * c);
        return 0.5 * t2 / (1.0 + std::sqrt(1.0 + t2));
    }
    const double a = c / (alpha * std::sqrt(s2));
    if (a > 26) return 0.0;
    return 0.5 * (std::exp(-a * a) / (a * std::sqrt(M_PI)) - std::erfc(a));
}
Vec3 oldSampleGgx(float alpha, Vec3 wo, float u1, float u2) {
    if (wo.z < 0) wo = -wo;
    const Vec3 vh = normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const Vec3 t1 = len2 > 0 ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : Vec3(1, 0, 0);
    const Vec3 t2 = cross(vh, t1);
    const float r = std::sqrt(u1);
    float sinPhi, cosPhi;
    sinCos2Pi(u2, sinPhi, cosPhi);
    const float p1 = r * cosPhi, s = 0.5f * (1.0f + vh.z);
    const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * sinPhi;
    const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
    return normalize(Vec3(alpha * nh.x, alpha * nh.y, std::max(1e-7f, nh.z)));
}
bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(Vec3 a, Vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A rough conductor or dielectric over distribution d.
struct Material {
    BsdfExtra x;
    BsdfParams p;
    Material(MaterialKind k, const Microfacet& d, float eta = 1.5f) {
        x.dist = d;
        p.kind = k;
        if (k == MaterialKind::Conductor || k == MaterialKind::RoughConductor)  // copper (veach-mis)
            setConductorIndex(p, Vec3(0.200438f, 0.924033f, 1.10221f), Vec3(3.91295f, 2.45285f, 2.14219f));
        p.eta = eta;
        p.reflect = Vec3(1.0f);
        p.refract = Vec3(1.0f);
        p.x = &x;
    }
    Material(const Material& o) : x(o.x), p(o.p) { p.x = &x; }
};
std::vector<Material> materialCases() {
    std::vector<Material> v;
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX}) {
        v.emplace_back(MaterialKind::RoughConductor, Microfacet(t, 0.05f, 0.5f));
        v.emplace_back(MaterialKind::RoughConductor, Microfacet(t, 0.4f, 0.15f));
        v.emplace_back(MaterialKind::RoughDielectric, Microfacet(t, 0.1f, 0.5f), 1.5f);
        v.emplace_back(MaterialKind::RoughDielectric, Microfacet(t, 0.6f, 0.2f), 1.0f / 1.33f);
    }
    return v;
}
double pdfIntegral(const Material& m, Vec3 wo) {
    double s = 0;
    for (double v : chi2::SphereBins::uniform(Vec3(-wo.x, -wo.y, wo.z), 24, 16).integrate([&](Vec3 w) { return bsdfPdf(m.p, wo, w); }, 1e-8, 10))
        s += v;
    return s;
}
}  // namespace

TEST_CASE("Anisotropic D and visible normals are normalised", "[bsdf][microfacet][aniso]") {
    for (const Microfacet& d : anisoCases()) {
        INFO(typeName(d.type) << " alpha " << d.alphaX << " x " << d.alphaY);
        double s = 0;  // projected area: int D(m) cos dm = 1
        for (double v :
             chi2::SphereBins::uniform({0, 0, 1}, 40, 8).integrate([&](Vec3 m) { return microfacetD(d, m) * std::max(0.0f, m.z); }, 1e-9, 12))
            s += v;
        CHECK(s == Approx(1.0).margin(2e-4));
        for (double th : {0.0, 40.0, 75.0, 89.0, 140.0})
            for (double ph : {0.0, 30.0, 90.0}) {  // Smith's Lambda is exact: int D_wo = 1
                Vec3 wo = dirAt(th, ph);
                double v = 0;
                for (double x : chi2::SphereBins::uniform({0, 0, 1}, 40, 16).integrate([&](Vec3 m) { return visibleNormalPdf(d, wo, m); }, 1e-9, 10))
                    v += x;
                INFO("theta " << th << " phi " << ph);
                CHECK(v == Approx(1.0).margin(3e-4));
            }
    }
}

TEST_CASE("Anisotropic visible normal sampling matches D_wo (chi-square)", "[bsdf][microfacet][aniso][chi2]") {
    int k = 0;
    for (const Microfacet& d : anisoCases())
        for (double th : {0.0, 45.0, 80.0, 120.0})
            for (double ph : {0.0, 70.0}) {
                if (th == 0.0 && ph != 0.0) continue;
                Vec3 wo = dirAt(th, ph);
                auto sample = [&](chi2::Pcg32& g, Vec3& w) {
                    w = sampleVisibleNormal(d, wo, g.uniform(), g.uniform());
                    return true;
                };
                auto r = chi2::sphereTest(
                    sample, [&](Vec3 m) { return visibleNormalPdf(d, wo, m); },
                    chi2::SphereBins::lobe({0, 0, 1}, 2 / (d.alphaX * d.alphaY), 12, 2, 24), 200000, 0, 700 + k++);
                INFO(typeName(d.type) << " alpha " << d.alphaX << " x " << d.alphaY << " theta " << th << " phi " << ph << " " << chi2::describe(r));
                CHECK(r.pValue > kMinP);
            }
}

TEST_CASE("Anisotropic rough conductor and dielectric: sampling matches the pdf, f/pdf of samples equal evaluation",
          "[bsdf][microfacet][aniso][chi2]") {
    int k = 0, mismatches = 0;
    for (const Material& m : materialCases())
        for (double th : {10.0, 70.0, 150.0})
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                if (mode == TransportMode::Importance && m.p.kind != MaterialKind::RoughDielectric) continue;
                Vec3 wo = dirAt(th, 200);
                auto sample = [&](chi2::Pcg32& g, Vec3& w) {
                    BsdfSample s;
                    float ul = g.uniform(), u1 = g.uniform(), u2 = g.uniform();
                    if (!bsdfSample(m.p, wo, ul, u1, u2, mode, s)) return false;
                    Vec3 f = mode == TransportMode::Radiance ? bsdfF(m.p, wo, s.wi) : bsdfF(m.p, s.wi, wo);
                    for (int c = 0; c < 3; ++c) mismatches += !close(s.f[c], f[c]);
                    mismatches += !close(s.pdf, bsdfPdf(m.p, wo, s.wi)) || !isFinite(s.f);
                    w = s.wi;
                    return true;
                };
                auto r = chi2::sphereTest(
                    sample, [&](Vec3 w) { return bsdfPdf(m.p, wo, w); }, chi2::SphereBins::uniform(Vec3(-wo.x, -wo.y, wo.z), 24, 16), 100000,
                    std::max(0.0, 1.0 - pdfIntegral(m, wo)), 800 + k++);
                INFO("kind " << int(m.p.kind) << " " << typeName(m.x.dist.type) << " alpha " << m.x.dist.alphaX << " x " << m.x.dist.alphaY << " eta "
                             << m.p.eta << " theta " << th << " " << chi2::describe(r));
                CHECK(r.pValue > kMinP);
            }
    CHECK(mismatches == 0);
}

TEST_CASE("Anisotropic microfacet BSDFs are reciprocal and conserve energy", "[bsdf][microfacet][aniso][reciprocity]") {
    chi2::Pcg32 g(21);
    int bad = 0, nonzero = 0, k = 0;
    for (const Material& m : materialCases()) {
        for (int i = 0; i < 20000; ++i) {
            Vec3 wo = sampleUniformSphere(g.uniform(), g.uniform()), wi = sampleUniformSphere(g.uniform(), g.uniform());
            Vec3 a = bsdfF(m.p, wo, wi), b = bsdfF(m.p, wi, wo);
            float e2 = 1;  // f(wi, wo) = f(wo, wi) eta'^2 across the dielectric (Veach 1997, 5.2)
            if (m.p.kind == MaterialKind::RoughDielectric && wo.z * wi.z < 0) e2 = wo.z > 0 ? m.p.eta * m.p.eta : 1 / (m.p.eta * m.p.eta);
            for (int c = 0; c < 3; ++c) bad += !close(a[c] * e2, b[c], 1e-3);
            nonzero += a[1] > 0;
        }
        for (double th : {0.0, 60.0, 85.0, 135.0})
            for (double ph : {0.0, 45.0, 90.0}) {
                Vec3 wo = dirAt(th, ph);
                chi2::Pcg32 h(950 + k++);
                const int N = 40000;
                double s = 0, s2 = 0;
                for (int i = 0; i < N; ++i) {
                    BsdfSample bs;
                    if (!bsdfSample(m.p, wo, h.uniform(), h.uniform(), h.uniform(), TransportMode::Importance, bs)) continue;
                    const double w = bs.f[1] * absCosTheta(bs.wi) / bs.pdf;
                    s += w;
                    s2 += w * w;
                }
                const double mean = s / N, se = std::sqrt(std::max(0.0, s2 / N - mean * mean) / N);
                INFO("kind " << int(m.p.kind) << " alpha " << m.x.dist.alphaX << " x " << m.x.dist.alphaY << " theta " << th << " phi " << ph
                             << " albedo " << mean << " se " << se);
                CHECK(mean <= 1 + 5 * se + 1e-5);
            }
    }
    CHECK(bad == 0);
    CHECK(nonzero > 40000);
}

TEST_CASE("Isotropic microfacets compute b069d67's values bit for bit, the anisotropic forms meet them", "[bsdf][microfacet][aniso][isotropic]") {
    chi2::Pcg32 g(5);
    int differ = 0, far = 0;
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float a : {1e-4f, 0.01f, 0.05f, 0.1f, 0.3f, 0.8f, 1.0f, 2.5f})
            for (int i = 0; i < 4000; ++i) {
                const Microfacet d(t, a);
                Vec3 m = sampleUniformSphere(g.uniform(), g.uniform());
                Vec3 w = sampleUniformSphere(g.uniform(), g.uniform());
                if (i % 8 == 0) m = normalize(Vec3(m.x * 1e-3f, m.y * 1e-3f, std::fabs(m.z)));  // near the pole
                if (i % 8 == 1) w.z = 0;                                                        // grazing
                const float u1 = g.uniform(), u2 = g.uniform();
                differ += !sameBits(microfacetD(d, m), oldD(t, a, m));
                differ += !sameBits(microfacetLambda(d, w), oldLambda(t, a, w));
                if (t == MicrofacetType::GGX) differ += !sameBits(sampleVisibleNormal(d, w, u1, u2), oldSampleGgx(a, w, u1, u2));
                // The anisotropic branch at alphaY one float step away: the same function.
                const Microfacet n(t, a, std::nextafter(a, 10.0f));
                REQUIRE(!n.isotropic());
                far += !close(microfacetD(n, m), microfacetD(d, m), 1e-5);
                far += !close(microfacetLambda(n, w), microfacetLambda(d, w), 1e-5) && std::isfinite(microfacetLambda(d, w));
                const Vec3 sa = sampleVisibleNormal(n, w, u1, u2), sb = sampleVisibleNormal(d, w, u1, u2);
                far += !(std::fabs(dot(sa, sb) - 1.0f) < 1e-5f);
            }
    CHECK(differ == 0);
    CHECK(far == 0);
}

TEST_CASE("Anisotropic microfacets: alphaX along x, alphaY along y", "[bsdf][microfacet][aniso]") {
    chi2::Pcg32 g(8);
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX}) {
        const Microfacet d(t, 0.1f, 0.6f), swapped(t, 0.6f, 0.1f), isoX(t, 0.1f), isoY(t, 0.6f);
        for (int i = 0; i < 2000; ++i) {
            const Vec3 m = sampleUniformSphere(g.uniform(), g.uniform());
            // D and Lambda turn with the axes: (ax, ay) at m = (ay, ax) at m turned by 90 degrees.
            CHECK(close(microfacetD(d, m), microfacetD(swapped, Vec3(-m.y, m.x, m.z)), 1e-5));
            CHECK(close(microfacetLambda(d, m), microfacetLambda(swapped, Vec3(-m.y, m.x, m.z)), 1e-5));
        }
        for (double th : {10.0, 50.0, 85.0}) {  // in the xz and yz planes Lambda is the isotropic one of that alpha
            CHECK(close(microfacetLambda(d, dirAt(th, 0)), microfacetLambda(isoX, dirAt(th, 0)), 1e-5));
            CHECK(close(microfacetLambda(d, dirAt(th, 90)), microfacetLambda(isoY, dirAt(th, 90)), 1e-5));
        }
        // A normal tilted along x (the smoother direction) is rarer than one tilted as far along y.
        CHECK(microfacetD(d, dirAt(20, 0)) < microfacetD(d, dirAt(20, 90)));
    }
}

namespace {
const std::string kSensor = R"(<sensor type="perspective"><float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
</sensor>
)";
std::string scene(const std::string& body) {
    return "<scene version=\"3.0.0\">\n" + kSensor + body +
           "\n<shape type=\"rectangle\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>\n</scene>\n";
}
SceneDesc load(const std::string& xml) { return loadMitsubaFromString(xml, "t.xml", ".", {}); }
std::string errorOf(const std::string& xml) {
    try {
        load(xml);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
std::string shapeWith(const std::string& bsdf) { return "<shape type=\"cube\">" + bsdf + "</shape>"; }
}  // namespace

TEST_CASE("Mitsuba import: alpha_u and alpha_v, refused where Mitsuba refuses them", "[mitsuba][import][aniso]") {
    SceneDesc d =
        load(scene(shapeWith(R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.5"/>
        <string name="distribution" value="ggx"/></bsdf>)") +
                   shapeWith(R"(<bsdf type="roughdielectric"><float name="alpha_u" value="0.3"/><float name="alpha_v" value="0.1"/></bsdf>)") +
                   shapeWith(R"(<bsdf type="roughplastic"><float name="alpha_u" value="0.2"/><float name="alpha_v" value="0.2"/></bsdf>)") +
                   shapeWith(R"(<bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf>)")));
    const MaterialDesc& c = d.materials[d.shapes[0].material];
    CHECK(c.alpha == 0.05f);
    CHECK(alphaVOf(c) == 0.5f);
    CHECK(isAnisotropic(c));
    const MaterialDesc& g = d.materials[d.shapes[1].material];
    CHECK((g.alpha == 0.3f && alphaVOf(g) == 0.1f && isAnisotropic(g)));
    const MaterialDesc& p = d.materials[d.shapes[2].material];
    CHECK((p.alpha == 0.2f && alphaVOf(p) == 0.2f && !isAnisotropic(p)));
    CHECK(!isAnisotropic(d.materials[d.shapes[3].material]));
    auto s = Scene::build(d, 1);
    CHECK(s->features.anisotropic);
    const Microfacet& dist = s->materials[d.shapes[0].material].x->dist;
    CHECK((dist.type == MicrofacetType::GGX && dist.alphaX == 0.05f && dist.alphaY == 0.5f));
    CHECK(s->materials[d.shapes[2].material].x->dist.isotropic());
    // Only materials some shape uses count: an unused anisotropic BSDF changes nothing.
    SceneDesc u =
        load(scene(R"(<bsdf type="roughconductor" id="unused"><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.5"/></bsdf>)" +
                   shapeWith(R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.2"/><float name="alpha_v" value="0.2"/></bsdf>)")));
    CHECK(!Scene::build(u, 1)->features.anisotropic);

    // Mitsuba 3: both or neither, not with alpha; roughplastic is isotropic only.
    CHECK(errorOf(scene(shapeWith(R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.1"/></bsdf>)"))).find("both alpha_u and alpha_v") !=
          std::string::npos);
    CHECK(errorOf(scene(shapeWith(R"(<bsdf type="roughdielectric"><float name="alpha_v" value="0.1"/></bsdf>)"))).find("both alpha_u and alpha_v") !=
          std::string::npos);
    CHECK(errorOf(scene(shapeWith(R"(<bsdf type="roughconductor"><float name="alpha" value="0.1"/><float name="alpha_u" value="0.1"/>
        <float name="alpha_v" value="0.2"/></bsdf>)")))
              .find("either alpha or alpha_u") != std::string::npos);
    const std::string e =
        errorOf(scene(shapeWith(R"(<bsdf type="roughplastic"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/></bsdf>)")));
    CHECK(e.find("not supported by roughplastic") != std::string::npos);
    CHECK(e.find("t.xml:") == 0);
    CHECK(errorOf(scene(shapeWith(R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0"/></bsdf>)")))
              .find("alpha must be in") != std::string::npos);
}

namespace {
// The shading frame at the hit of a ray straight down onto (x, y).
Frame frameAt(const Scene& s, float x, float y) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = x;
    rh.ray.org_y = y;
    rh.ray.org_z = 5;
    rh.ray.dir_z = -1;
    rh.ray.tfar = INFINITY;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(s.rtc, &ctx, &rh);
    REQUIRE(rh.hit.geomID != RTC_INVALID_GEOMETRY_ID);
    using All = SurfaceFeatures<true, true, true, true, true>;
    return shadingFrame<All>(s, surfaceAt<All>(s, rh));
}
}  // namespace

TEST_CASE("Anisotropic materials' shading frames follow dp/du", "[mitsuba][aniso][frame]") {
    const std::string aniso = R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.5"/></bsdf>)";
    const std::string iso = R"(<bsdf type="roughconductor"><float name="alpha" value="0.05"/></bsdf>)";
    auto rect = [](const std::string& bsdf, const std::string& transform) {
        return "<shape type=\"rectangle\">" + bsdf + "<transform name=\"to_world\">" + transform + "</transform></shape>";
    };
    SceneDesc d = load(scene(rect(aniso, "<translate x=\"10\"/>") + rect(aniso, "<rotate z=\"1\" angle=\"90\"/><translate x=\"20\"/>") +
                             rect(iso, "<rotate z=\"1\" angle=\"30\"/><translate x=\"30\"/>") +
                             "<shape type=\"sphere\"><transform name=\"to_world\"><translate x=\"40\"/></transform>" + aniso + "</shape>"));
    auto s = Scene::build(d, 1);
    REQUIRE(s->features.anisotropic);
    // The rectangle's u runs along its local +x: world +x, then +y when turned about z.
    const Frame a = frameAt(*s, 10.2f, 0.3f), b = frameAt(*s, 20.2f, 0.3f);
    CHECK(a.n.z == Approx(1.0f));
    CHECK(a.s.x == Approx(1.0f).margin(1e-6));
    CHECK(b.s.y == Approx(1.0f).margin(1e-6));
    CHECK(std::fabs(dot(b.t, b.s)) < 1e-6f);
    CHECK(dot(cross(b.s, b.t), b.n) == Approx(1.0f));  // right-handed, as fromNormal's
    // An isotropic material keeps fromNormal's frame, bit for bit.
    const Frame c = frameAt(*s, 30.2f, 0.3f), f = Frame::fromNormal(c.n);
    CHECK((sameBits(c.s, f.s) && sameBits(c.t, f.t)));
    // Mitsuba's sphere: u is the azimuth about its z axis, dp/du = (-y, x, 0) at the top of x.
    const Frame e = frameAt(*s, 40.0f + 0.6f, 0.0f);
    CHECK(e.s.y == Approx(1.0f).margin(1e-5));
}
