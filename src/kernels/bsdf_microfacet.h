// The Mitsuba 3 materials (docs/mitsuba.md), in bsdf.h's conventions. Included by bsdf.h;
// include that instead. Parameters: BsdfParams::reflect = specular_reflectance, refract =
// specular_transmittance, diffuse = diffuse_reflectance, eta = int_ior / ext_ior, and the
// constants in BsdfParams::x (microfacet distribution, conductor index, plastic tables).
//
// Reflecting kinds are two-sided here (they scatter into wo's hemisphere, computed as if
// wo were above); Mitsuba's one-sided back faces are made black per hit (surface.cpp).
#pragma once

namespace wmlt {

// Conductor (smooth, delta): mirror, weight F_conductor(cos) * reflect.
bool conductorSample(const BsdfParams& m, Vec3 wo, BsdfSample& s);

// Rough conductor (Walter 2007, eq. 20): f = reflect F(wo.h) D(h) G / (4 |cos_o| |cos_i|),
// sampled by visible normals: pdf = D_wo(h) / (4 wo.h).
Vec3 roughConductorF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float roughConductorPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool roughConductorSample(const BsdfParams& m, Vec3 wo, float u1, float u2, BsdfSample& s);

// Thin dielectric (delta; Mitsuba's thindielectric): a slab with both faces parallel;
// R = F + T^2 F / (1 - F^2) over all internal bounces, reflection or straight through
// (wi = -wo) with probability R and 1 - R. No 1/eta^2: the light leaves where it entered.
bool thinDielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, BsdfSample& s);

// Rough dielectric (Walter 2007, eqs. 20-21; pbrt-v4 9.7), the normal pointing outside as
// for Dielectric. Reflection with probability F(wo.m) of the sampled visible normal m,
// refraction otherwise; radiance-mode f carries 1/eta'^2 on refraction (eta' = n_i / n_o).
Vec3 roughDielectricF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float roughDielectricPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool roughDielectricSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, TransportMode mode, BsdfSample& s);

// Plastic (Mitsuba's `plastic`): a smooth dielectric coating (delta mirror, weight
// reflect * F_i) over a diffuse base seen through it: f = Kd' (1 - F_i)(1 - F_o) / (eta^2 pi),
// Kd' = Kd / (1 - Fdr_int) (or Kd / (1 - Kd Fdr_int) when nonlinear), Fdr_int the coating's
// diffuse reflectance from inside (internal scattering summed as a geometric series).
// The coating is chosen with probability F_i w / (F_i w + (1 - F_i)(1 - w)), w the
// specular sampling weight. f and pdf below are the diffuse part (the delta is sampled only).
Vec3 plasticF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float plasticPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool plasticSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s);

// Rough plastic (Mitsuba's `roughplastic`): a rough dielectric coating's reflection
// (as a rough conductor with dielectric Fresnel) plus the base seen through it:
// Kd' T(cos_o) T(cos_i) / (eta^2 pi), T the coating's transmittance table, Fdr_int from the
// rough coating. Coating chosen with probability (1 - T_o) w / ((1 - T_o) w + T_o (1 - w)).
// Isotropic only, as Mitsuba 3's: T is tabulated over cos alone (the importer refuses
// alpha_u != alpha_v here).
Vec3 roughPlasticF(const BsdfParams& m, Vec3 wo, Vec3 wi);
float roughPlasticPdf(const BsdfParams& m, Vec3 wo, Vec3 wi);
bool roughPlasticSample(const BsdfParams& m, Vec3 wo, float uLobe, float u1, float u2, BsdfSample& s);

// Fills x's plastic constants for relative index eta: fdrInt (smooth coating when
// !rough) and, when rough, the transmittance table and Fdr_int of the rough coating
// (numerical integration over the visible normals; allocation-free, but 25-80 ms per
// rough material at scene build: ~26 ms GGX, ~80 ms Beckmann, measured with -O2).
void preparePlastic(BsdfExtra& x, float eta, bool rough);

}  // namespace wmlt
