// Linear RGB float images and their files (EXR, PFM, PNG, JPEG, HDR).
#pragma once
#include <string>
#include <vector>

#include "wavemmlt/math.h"

namespace wmlt {

// Row-major, top row first, 3 floats per pixel, linear RGB.
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
    Vec3 at(int x, int y) const {
        const float* p = &rgb[(size_t(y) * width + x) * 3];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, Vec3 c) {
        float* p = &rgb[(size_t(y) * width + x) * 3];
        p[0] = c.x;
        p[1] = c.y;
        p[2] = c.z;
    }
};

// Reads .exr, .pfm, .hdr (linear) and .png, .jpg/.jpeg (sRGB, linearised).
// Throws InputError("path: problem") on a missing, unreadable, truncated or empty file.
Image readImage(const std::string& path);

// Writes by extension: .exr (float RGB), .pfm (float RGB), .png (8-bit sRGB after
// multiplying by 2^exposure, clamped). Writes to a temporary name in the same folder,
// then renames, so a failed or interrupted write never leaves a partial file.
// Throws InputError naming the path on an unknown extension or an unwritable folder.
void writeImage(const std::string& path, const Image& image, float exposure = 0.0f);

// True when the extension is one writeImage accepts (.exr, .pfm, .png; case-insensitive).
bool isWritableImageExtension(const std::string& path);

// What a PNG file holds (and the --view window shows): each channel times 2^exposure,
// through the sRGB curve, clamped to [0, 1] (NaN as 0), rounded to 8 bits; 3 bytes per
// pixel, top row first.
std::vector<unsigned char> toSrgb8(const Image& image, float exposure);

// sRGB transfer functions (IEC 61966-2-1).
float srgbToLinear(float v);
float linearToSrgb(float v);

}  // namespace wmlt
