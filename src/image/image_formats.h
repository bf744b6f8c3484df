// Internal to src/image/: the per-format readers and writers behind readImage/writeImage
// (image_io.cpp dispatches on the extension). Readers throw InputError naming `path`;
// writers write to an open temporary file and throw std::runtime_error on failure
// (writeImage turns it into an InputError naming the destination and removes the file).
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>

#include "wavemmlt/image.h"

namespace wmlt {
namespace imageio {

// Refuse images larger than this before allocating (a corrupt header claiming
// 1e6 x 1e6 pixels must not exhaust memory): at most 2^20 pixels on a side and
// 2^28 pixels (3 GiB of float RGB) in all.
constexpr int64_t kMaxDimension = int64_t(1) << 20;
constexpr int64_t kMaxPixels = int64_t(1) << 28;

// Throws InputError(path, "...") unless 0 < w, h and the size is within the limits.
void checkSize(const std::string& path, int64_t w, int64_t h);

// Throws InputError(path, "cannot open: <reason>") unless path names a readable file.
void checkReadable(const std::string& path);

// The whole file, or an InputError naming the path and the system's reason.
std::string readFileBytes(const std::string& path);

Image readExr(const std::string& path);
void writeExr(const std::string& tmpPath, const Image& image);

Image readPfm(const std::string& path);
void writePfm(std::FILE* f, const Image& image);

Image readHdr(const std::string& path);

}  // namespace imageio
}  // namespace wmlt
