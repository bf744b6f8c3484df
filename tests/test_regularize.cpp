// pbrt-v4's path regularisation (Integrator "bool regularize"; scene/regularize.h): the rule
// on a roughness, the regularized materials and their table in the Scene, the texture stage's
// regularized alphas; and renders of a diffuse floor under a smooth mirror ceiling lit by spot
// lights: PT and BPT agree where every mirror vertex lies between two diffuse ones (so both
// of BPT's subpaths regularize it, as PT does), the regularized image differs where the mirror
// reflection blurs, PT's next-event estimation through the regularized mirror lights a caustic
// that the unregularized PT cannot see, paths whose mirror vertex has no diffuse bounce before
// it are unchanged bit for bit, and LT, MMLT and PSSMLT render without it.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "kernels/textured_params.h"
#include "render_stats.h"
#include "scene/regularize.h"
#include "scene/scene.h"
#include "wavemmlt/render.h"
#include "wavemmlt/scene_desc.h"

using namespace wmlt;

namespace {

SceneDesc loadText(const std::string& name, const std::string& text) {
    static const std::string dir = rstats::tempDir("regularize");
    const std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return loadScene(path);
}

// A 16 x 16 view (camera at `eye` looking at `at`) of a diffuse floor (y = 0, reflectance 0.5)
// under a smooth mirror (pbrt's conductor, reflectance 0.9) over x in [-0.5, 1], z in [-1, 1]
// at y = 1, facing down. Spot B, at height 0.3 over x = -1.5, lights a floor patch Q below it
// (cone 60 degrees) and never the mirror; spot A (caustic: true), at (1.5, 0.3, 0), shines up at
// the mirror only (cone 10 degrees), which reflects it onto the floor around x = -0.9.
std::string mirrorRoom(bool regularize, const std::string& eye, const std::string& at, bool caustic, int maxDepth) {
    return std::string("Integrator \"path\" \"integer maxdepth\" [ ") + std::to_string(maxDepth) + " ]" +
           (regularize ? " \"bool regularize\" true" : "") + "\nLookAt " + eye + "  " + at + R"(  0 0 1
Camera "perspective" "float fov" [ 60 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
PixelFilter "box"
WorldBegin
LightSource "spot" "point3 from" [ -1.5 0.3 0 ] "point3 to" [ -1.5 0 0 ] "float coneangle" 60 "rgb I" [ 10 10 10 ]
)" +
           (caustic ? R"(LightSource "spot" "point3 from" [ 1.5 0.3 0 ] "point3 to" [ 0.5 1 0 ] "float coneangle" 10 "rgb I" [ 10 10 10 ]
)"
                    : "") +
           R"(AttributeBegin
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeEnd
AttributeBegin
Material "conductor" "rgb reflectance" [ 0.9 0.9 0.9 ]
Shape "trianglemesh" "point3 P" [ -0.5 1 -1  1 1 -1  1 1 1  -0.5 1 1 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
)";
}

// K renders of d by `tracer` (seeds seed0 ..), as block means of 4 x 4 pixels (green).
rstats::RunStats runs(const SceneDesc& d, TracerKind tracer, int spp, int maxLength, int K, uint64_t seed0) {
    rstats::RunStats r;
    for (int k = 0; k < K; ++k)
        r.add(rstats::blockMeans(render(d, rstats::renderOptions(tracer, spp, seed0 + uint64_t(k), 1, maxLength)).image, 4, 1));
    return r;
}

// The mean over blocks `blocks` of r's per-run values, and its standard error (from the runs).
void regionMean(const rstats::RunStats& r, const std::vector<size_t>& blocks, double& mean, double& se) {
    double m = 0, v = 0;
    for (size_t b : blocks) m += r.mean(b);
    mean = m / double(blocks.size());
    // the blocks' run means are independent estimates (disjoint pixels): their variances add
    for (size_t b : blocks) v += r.variance(b) / r.runs;
    se = std::sqrt(v) / double(blocks.size());
}

}  // namespace

TEST_CASE("regularize: pbrt-v4's rule on a roughness", "[regularize]") {
    CHECK(regularizedAlpha(0.0f) == 0.1f);
    CHECK(regularizedAlpha(1e-4f) == 0.1f);
    CHECK(regularizedAlpha(0.05f) == 0.1f);
    CHECK(regularizedAlpha(0.1f) == 0.2f);
    CHECK(regularizedAlpha(0.2f) == 0.3f);
    CHECK(regularizedAlpha(0.29f) == 0.3f);
    CHECK(regularizedAlpha(0.3f) == 0.3f);
    CHECK(regularizedAlpha(0.5f) == 0.5f);
    CHECK(regularizedAlpha(2.0f) == 2.0f);
}

TEST_CASE("regularize: the regularized materials", "[regularize]") {
    MaterialDesc glass;
    glass.kind = MaterialKind::Dielectric;
    MaterialDesc r = regularizedMaterial(glass);
    CHECK(r.kind == MaterialKind::RoughDielectric);
    CHECK(r.distribution == MicrofacetType::GGX);
    CHECK(r.alpha == 0.1f);
    CHECK(alphaVOf(r) == 0.1f);
    CHECK(r.iorInside == glass.iorInside);

    MaterialDesc metal;
    metal.kind = MaterialKind::Conductor;
    metal.conductorK = Vec3(3.0f);
    r = regularizedMaterial(metal);
    CHECK(r.kind == MaterialKind::RoughConductor);
    CHECK(r.alpha == 0.1f);
    CHECK(r.conductorK.x == 3.0f);

    MaterialDesc brushed;  // anisotropic: each alpha by the rule
    brushed.kind = MaterialKind::RoughConductor;
    brushed.alpha = 0.05f;
    brushed.alphaV = 0.2f;
    r = regularizedMaterial(brushed);
    CHECK(r.alpha == 0.1f);
    CHECK(r.alphaV == 0.3f);
    brushed.alpha = brushed.alphaV = 0.5f;
    CHECK(regularizedMaterial(brushed).alpha == 0.5f);

    MaterialDesc coat;  // the interface and the conductor base
    coat.kind = MaterialKind::Coated;
    coat.alpha = 0;
    coat.alphaV = 0;
    coat.coating.conductorBase = true;
    coat.coating.baseAlpha = 0.02f;
    coat.coating.baseAlphaV = 0.4f;
    r = regularizedMaterial(coat);
    CHECK(r.alpha == 0.1f);
    CHECK(alphaVOf(r) == 0.1f);
    CHECK(r.coating.baseAlpha == 0.1f);
    CHECK(r.coating.baseAlphaV == 0.4f);

    MaterialDesc textured;  // the constants stay: the texture stage regularizes per hit
    textured.kind = MaterialKind::RoughDielectric;
    textured.alpha = 1;
    textured.texture[MaterialParam::AlphaU] = 0;
    r = regularizedMaterial(textured);
    CHECK(r.alpha == 1.0f);
    CHECK(r.texture[MaterialParam::AlphaU] == 0);

    for (MaterialKind k : {MaterialKind::Matte, MaterialKind::DiffuseTransmission, MaterialKind::ThinDielectric, MaterialKind::Blend}) {
        MaterialDesc m;
        m.kind = k;
        CHECK(regularizedMaterial(m).kind == k);
    }
}

TEST_CASE("regularize: a textured roughness is regularized at the hit, after its texture", "[regularize]") {
    std::vector<TextureDesc> tex(1);
    tex[0].kind = TextureKind::Checker;
    tex[0].colour1 = tex[0].colour2 = Vec3(0.0004f);  // a roughness of 0.0004: alpha sqrt(0.0004) = 0.02
    MaterialDesc m;
    m.kind = MaterialKind::RoughConductor;
    m.distribution = MicrofacetType::GGX;
    m.alpha = 1;
    m.texture[MaterialParam::AlphaU] = m.texture[MaterialParam::AlphaV] = 0;
    m.alphaRemap = true;
    for (bool regularized : {false, true}) {
        BsdfExtra x;
        x.dist = Microfacet(MicrofacetType::GGX, 1.0f);
        x.regularized = regularized;
        BsdfParams out;
        out.kind = MaterialKind::RoughConductor;
        out.x = &x;
        texturedParams(tex, m, 0.3f, 0.3f, Vec3(0.0f), Vec3(0, 1, 0), out);
        INFO("regularized " << regularized);
        CHECK(out.alphaX == Approx(regularized ? 0.1f : 0.02f).epsilon(1e-5));
        CHECK(out.alphaY == out.alphaX);
    }
}

TEST_CASE("regularize: the scene's regularized table", "[regularize][pbrt]") {
    const std::string text = R"(LookAt 0 1 -3  0 0 0  0 1 0
Camera "perspective"
Film "rgb" "integer xresolution" [ 8 ] "integer yresolution" [ 8 ]
WorldBegin
LightSource "point" "point3 from" [ 0 2 0 ]
MakeNamedMaterial "glass" "string type" "dielectric"
MakeNamedMaterial "floor" "string type" "diffuse"
MakeNamedMaterial "both" "string type" "mix" "string materials" [ "glass" "floor" ]
NamedMaterial "both"
Shape "sphere" "float radius" 0.5
NamedMaterial "glass"
Translate 1 0 0
Shape "sphere" "float radius" 0.5
)";
    const SceneDesc plain = loadText("table.pbrt", "Integrator \"path\"\n" + text);
    CHECK_FALSE(plain.regularize);
    const std::unique_ptr<Scene> a = Scene::build(plain, 1);
    CHECK(a->regularizedOffset == 0);
    CHECK(a->materials.size() == plain.materials.size());
    CHECK_FALSE(a->features.has(MaterialKind::RoughDielectric));

    const SceneDesc d = loadText("table.pbrt", "Integrator \"path\" \"bool regularize\" true\n" + text);
    REQUIRE(d.regularize);
    CHECK_THAT(d.regularizeAt, Catch::EndsWith("table.pbrt:1"));
    const std::unique_ptr<Scene> s = Scene::build(d, 1);
    const size_t n = d.materials.size();
    REQUIRE(s->regularizedOffset == n);
    REQUIRE(s->materials.size() == 2 * n);
    size_t blend = n;
    for (size_t i = 0; i < n; ++i) {
        INFO("material " << i);
        CHECK(s->materials[n + i].kind == regularizedMaterial(d.materials[i]).kind);
        if (d.materials[i].kind == MaterialKind::Blend) blend = i;
    }
    REQUIRE(blend < n);
    // the regularized blend's parts are the regularized parts; the blend itself the plain ones
    CHECK(s->materials[n + blend].x->blendParts[0].kind == MaterialKind::RoughDielectric);
    CHECK(s->materials[n + blend].x->blendParts[0].x->dist.alphaX == 0.1f);
    CHECK(s->materials[blend].x->blendParts[0].kind == MaterialKind::Dielectric);
    // the stages' kinds: the glass sphere's regularized version is a rough dielectric
    CHECK(s->features.has(MaterialKind::RoughDielectric));
}

TEST_CASE("regularize: PT and BPT agree where every mirror vertex lies between two diffuse vertices", "[regularize][render][stat]") {
    // The camera (under the mirror, looking down) sees the floor around x = 0.5 only, lit by the
    // patch Q through the mirror: camera - floor - mirror - Q - spot B. Spot B never lights the
    // mirror and the camera never sees it: each mirror vertex of each strategy has a diffuse
    // vertex before it on both subpaths, so BPT's camera and light subpaths both regularize
    // it, and BPT's strategies estimate PT's regularized image.
    const int maxLength = 5, K = 8, spp = 256;
    const SceneDesc reg = loadText("between.pbrt", mirrorRoom(true, "0.5 0.9 0", "0.5 0 0", false, maxLength - 1));
    const SceneDesc plain = loadText("between-plain.pbrt", mirrorRoom(false, "0.5 0.9 0", "0.5 0 0", false, maxLength - 1));
    const rstats::RunStats pt = runs(reg, TracerKind::PT, spp, maxLength, K, 100);
    const rstats::RunStats bpt = runs(reg, TracerKind::BPT, spp, maxLength, K, 200);
    double ratio = 0;
    const rstats::ZTestResult z = rstats::compareRuns(bpt, pt, 1e-4, &ratio);
    INFO("BPT against PT, both regularized: " << z.describe() << ", ratio of means " << ratio);
    CHECK(z.pass);
    // The blocks of the image's left column see floor points whose mirror reflection of Q
    // misses the mirror (past its edge x = -0.5): unregularized they get only the longer
    // paths' light; the regularized mirror's lobe reaches them.
    const rstats::RunStats unreg = runs(plain, TracerKind::PT, spp, maxLength, K, 300);
    double mReg, seReg, mUnreg, seUnreg;
    const std::vector<size_t> left = {0, 4, 8, 12};
    regionMean(pt, left, mReg, seReg);
    regionMean(unreg, left, mUnreg, seUnreg);
    const double zDiff = (mReg - mUnreg) / std::sqrt(seReg * seReg + seUnreg * seUnreg);
    const double bound = rstats::studentQuantileTwoSided(1e-4, K - 1);
    INFO("left column: regularized " << mReg << " +- " << seReg << ", unregularized " << mUnreg << " +- " << seUnreg << ": z " << zDiff
                                     << " (must exceed " << bound << ")");
    CHECK(zDiff > bound);
}

TEST_CASE("regularize: PT's light sampling through a regularized mirror, what it leaves unchanged", "[regularize][render][stat]") {
    // Spot A shines on the mirror only and a point light cannot be hit: the floor below the
    // mirror (seen from above, Q out of view) is lit only by the caustic, camera - floor -
    // mirror - spot A (3 segments: pbrt's maxdepth 2). Unregularized, PT finds none of it
    // (no light sampling at a specular vertex); regularized, the mirror after the floor's
    // diffuse bounce is rough (alpha 0.1) and its light sampling lights the caustic.
    const int maxLength = 3, K = 16, spp = 1024;
    const SceneDesc reg = loadText("caustic.pbrt", mirrorRoom(true, "-0.4 0.9 0", "-0.4 0 0", true, maxLength - 1));
    const SceneDesc plain = loadText("caustic-plain.pbrt", mirrorRoom(false, "-0.4 0.9 0", "-0.4 0 0", true, maxLength - 1));
    const Image none = render(plain, rstats::renderOptions(TracerKind::PT, spp, 1, 1, maxLength)).image;
    double maxUnreg = 0;
    for (float v : none.rgb) maxUnreg = std::max(maxUnreg, double(v));
    CHECK(maxUnreg == 0);
    const rstats::RunStats pt = runs(reg, TracerKind::PT, spp, maxLength, K, 400);
    std::vector<size_t> all(pt.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    double m, se;
    regionMean(pt, all, m, se);
    const double bound = rstats::studentQuantileTwoSided(1e-4, K - 1);
    INFO("regularized caustic: " << m << " +- " << se << " (z must exceed " << bound << ")");
    CHECK(m > bound * se);

    // The camera under the mirror sees Q in it: camera - mirror - Q - spot B. The mirror is the
    // path's first vertex (no non-specular bounce before it): not regularized, and with 3
    // segments no later vertex can be either. The same numbers give the same image, bit for bit.
    const SceneDesc view = loadText("view.pbrt", mirrorRoom(true, "0.5 0.3 0", "-1.5 2 0", true, maxLength - 1));
    const SceneDesc viewPlain = loadText("view-plain.pbrt", mirrorRoom(false, "0.5 0.3 0", "-1.5 2 0", true, maxLength - 1));
    const Image a = render(view, rstats::renderOptions(TracerKind::PT, spp, 7, 1, maxLength)).image;
    const Image b = render(viewPlain, rstats::renderOptions(TracerKind::PT, spp, 7, 1, maxLength)).image;
    double sum = 0;
    for (float v : a.rgb) sum += v;
    CHECK(sum > 0);  // Q's reflection is in view
    CHECK(a.rgb == b.rgb);

    // The light tracer and the Metropolis tracers render without it: the same image as the
    // scene without regularize, bit for bit (the caustic view, a few samples).
    for (TracerKind t : {TracerKind::LT, TracerKind::MMLT, TracerKind::PSSMLT}) {
        RenderOptions o = rstats::renderOptions(t, 4, 9, 1, maxLength);
        o.chains = 64;
        INFO("tracer " << int(t));
        CHECK(render(reg, o).image.rgb == render(plain, o).image.rgb);
    }
}
