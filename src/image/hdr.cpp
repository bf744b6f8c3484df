// Radiance RGBE (.hdr). Decoded here rather than by stb_image: stb_image 2.27 (Debian 12)
// loops forever on a truncated run-length-encoded file. The conversion is stb_image's
// (value = byte * 2^(exponent - 136), exponent 0 = black), so results match stbi_loadf
// on intact files. Header: "#?RADIANCE" or "#?RGBE", lines up to an empty line (FORMAT
// must be 32-bit_rle_rgbe; EXPOSURE is ignored, as stb_image and pbrt do), then
// "-Y H +X W" (or "+Y H +X W", bottom row first). Scanlines: flat, old-style runs
// (1,1,1,n) or new-style per-component RLE.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "image/image_formats.h"
#include "wavemmlt/error.h"

namespace wmlt {
namespace imageio {

Image readHdr(const std::string& path) {
    const std::string bytes = readFileBytes(path);
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const size_t size = bytes.size();
    size_t pos = 0;
    auto line = [&](std::string& out) {
        out.clear();
        while (pos < size && data[pos] != '\n') {
            if (out.size() > 4096) throw InputError(path, 0, "bad Radiance header (line too long)");
            out += char(data[pos++]);
        }
        if (pos >= size) throw InputError(path, 0, "truncated Radiance header");
        ++pos;
        if (!out.empty() && out.back() == '\r') out.pop_back();
    };
    std::string l;
    if (size < 2 || data[0] != '#' || data[1] != '?') throw InputError(path, 0, "not a Radiance HDR file (no \"#?\" signature)");
    line(l);
    for (;;) {
        line(l);
        if (l.empty()) break;
        if (l.compare(0, 7, "FORMAT=") == 0 && l != "FORMAT=32-bit_rle_rgbe")
            throw InputError(path, 0, "unsupported Radiance " + l + " (only 32-bit_rle_rgbe)");
    }
    line(l);
    char ys[3] = {0}, xs[3] = {0};
    long long hh = -1, ww = -1;
    char extra = 0;
    if (std::sscanf(l.c_str(), "%2s %lld %2s %lld %c", ys, &hh, xs, &ww, &extra) != 4 || (std::strcmp(ys, "-Y") != 0 && std::strcmp(ys, "+Y") != 0) ||
        std::strcmp(xs, "+X") != 0)
        throw InputError(path, 0, "unsupported Radiance resolution line '" + l + "' (expected \"-Y H +X W\")");
    checkSize(path, ww, hh);
    const bool bottomUp = ys[0] == '+';
    const int w = int(ww), h = int(hh);

    auto truncated = [&](int row) {
        return InputError(path, 0, "truncated Radiance data (scanline " + std::to_string(row + 1) + " of " + std::to_string(h) + ")");
    };
    auto corrupt = [&](int row) { return InputError(path, 0, "corrupt Radiance data (scanline " + std::to_string(row + 1) + ")"); };
    // The pixels grow scanline by scanline as they decode, so a short file that claims a huge
    // size fails before it has cost more memory than its data can fill (fuzz_hdr).
    Image img;
    img.width = w;
    img.height = h;
    std::vector<unsigned char> rgbe(size_t(w) * 4);
    for (int row = 0; row < h; ++row) {
        const bool newRle = w >= 8 && w < 32768 && pos + 4 <= size && data[pos] == 2 && data[pos + 1] == 2 && (data[pos + 2] & 0x80) == 0;
        if (newRle) {
            if (((data[pos + 2] << 8) | data[pos + 3]) != w) throw corrupt(row);
            pos += 4;
            for (int c = 0; c < 4; ++c) {
                int i = 0;
                while (i < w) {
                    if (pos >= size) throw truncated(row);
                    int count = data[pos++];
                    if (count > 128) {
                        count -= 128;
                        if (count > w - i) throw corrupt(row);
                        if (pos >= size) throw truncated(row);
                        unsigned char v = data[pos++];
                        for (int k = 0; k < count; ++k) rgbe[size_t(i++) * 4 + c] = v;
                    } else {
                        if (count == 0 || count > w - i) throw corrupt(row);
                        if (pos + size_t(count) > size) throw truncated(row);
                        for (int k = 0; k < count; ++k) rgbe[size_t(i++) * 4 + c] = data[pos++];
                    }
                }
            }
        } else {
            int i = 0, shift = 0;
            while (i < w) {
                if (pos + 4 > size) throw truncated(row);
                const unsigned char* p = data + pos;
                pos += 4;
                if (p[0] == 1 && p[1] == 1 && p[2] == 1) {  // old-style run of the previous pixel
                    if (i == 0) throw corrupt(row);
                    long long count = (long long)p[3] << shift;
                    if (count > w - i) throw corrupt(row);
                    for (long long k = 0; k < count; ++k, ++i) std::memcpy(&rgbe[size_t(i) * 4], &rgbe[size_t(i - 1) * 4], 4);
                    shift += 8;
                    if (shift > 24) throw corrupt(row);
                } else {
                    std::memcpy(&rgbe[size_t(i++) * 4], p, 4);
                    shift = 0;
                }
            }
        }
        img.rgb.resize(size_t(row + 1) * size_t(w) * 3);  // rows in file order; flipped below
        float* out = &img.rgb[size_t(row) * size_t(w) * 3];
        for (int x = 0; x < w; ++x) {
            const unsigned char* p = &rgbe[size_t(x) * 4];
            if (p[3] == 0) {
                out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = 0;
            } else {
                const float f = std::ldexp(1.0f, int(p[3]) - 136);
                out[3 * x] = p[0] * f;
                out[3 * x + 1] = p[1] * f;
                out[3 * x + 2] = p[2] * f;
            }
        }
    }
    if (bottomUp)
        for (int y = 0; y < h / 2; ++y)
            std::swap_ranges(img.rgb.begin() + ptrdiff_t(y) * w * 3, img.rgb.begin() + ptrdiff_t(y + 1) * w * 3,
                             img.rgb.begin() + ptrdiff_t(h - 1 - y) * w * 3);
    return img;
}

}  // namespace imageio
}  // namespace wmlt
