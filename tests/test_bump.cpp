// Bump mapping: the perturbed normal is the normal of the displaced surface.
#include <catch2/catch.hpp>

#include "kernels/bump.h"

using namespace wmlt;

namespace {

// An image texture whose luminance rises linearly with u: grey (x + 0.5) / 64 per column.
TextureDesc rampTexture() {
    TextureDesc t;
    t.kind = TextureKind::ImageFile;
    t.image = Image(64, 1);
    for (int x = 0; x < 64; ++x) t.image.set(x, 0, Vec3((x + 0.5f) / 64.0f));
    return t;
}

}  // namespace

TEST_CASE("bump: a constant height leaves the shading normal alone", "[bump]") {
    TextureDesc t;
    t.kind = TextureKind::Checker;
    t.colour1 = t.colour2 = Vec3(0.7f);
    Vec3 n = bumpedNormal(t, Vec3(1, 2, 3), 0.3f, 0.6f, Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(0, 0, 2));
    CHECK(n.x == Approx(0.0f).margin(1e-6));
    CHECK(n.y == Approx(1.0f));
    CHECK(n.z == Approx(0.0f).margin(1e-6));
}

TEST_CASE("bump: a height rising along u tilts the normal against u", "[bump]") {
    TextureDesc t = rampTexture();
    // A plane with normal +y, u along +x and v along +z, patch size 1.
    Vec3 n = bumpedNormal(t, Vec3(0.0f), 0.4f, 0.5f, Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1));
    // Height h = kBumpScale * u (slope 1 in luminance per unit u): n ~ (-kBumpScale, 1, 0).
    CHECK(n.x / n.y == Approx(-kBumpScale).epsilon(0.02));
    CHECK(n.z == Approx(0.0f).margin(1e-5));
    CHECK(length(n) == Approx(1.0f));
    // Scaling the surface (dp/du, dp/dv) scales the displacement too: the same tilt.
    Vec3 n2 = bumpedNormal(t, Vec3(0.0f), 0.4f, 0.5f, Vec3(0, 1, 0), Vec3(1000, 0, 0), Vec3(0, 0, 1000));
    CHECK(n2.x == Approx(n.x).epsilon(1e-3));
    CHECK(n2.y == Approx(n.y).epsilon(1e-3));
}

TEST_CASE("bump: the result stays on the shading normal's side", "[bump]") {
    TextureDesc t = rampTexture();
    // dp/du x dp/dv points to -y here; the bumped normal must still point to +y.
    Vec3 n = bumpedNormal(t, Vec3(0.0f), 0.4f, 0.5f, Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 0, 0));
    CHECK(n.y > 0.99f);
}
