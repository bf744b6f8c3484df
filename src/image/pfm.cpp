// Portable float map: "PF" (RGB) or "Pf" (grey), width, height, scale (negative: little-
// endian, positive: big-endian; |scale| multiplies the data), each separated by white
// space, then one white-space byte and the float rows, BOTTOM row first.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "image/image_formats.h"
#include "wavemmlt/error.h"

namespace wmlt {
namespace imageio {

namespace {

bool hostIsLittleEndian() {
    const uint32_t one = 1;
    unsigned char b;
    std::memcpy(&b, &one, 1);
    return b == 1;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

}  // namespace

Image readPfm(const std::string& path) {
    checkReadable(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, 0, "cannot open");
    in.seekg(0, std::ios::end);
    std::streamoff fileSize = in.tellg();
    in.seekg(0, std::ios::beg);
    if (fileSize < 0) throw InputError(path, 0, "cannot read: is it a regular file?");

    // Header: at most a few dozen bytes; read up to 256.
    std::string head(size_t(std::min<std::streamoff>(fileSize, 256)), '\0');
    in.read(&head[0], std::streamsize(head.size()));
    if (head.size() < 2 || head[0] != 'P' || (head[1] != 'F' && head[1] != 'f'))
        throw InputError(path, 0, "not a PFM file (expected \"PF\" or \"Pf\")");
    const int channels = head[1] == 'F' ? 3 : 1;
    size_t pos = 2;
    auto token = [&](const char* what) {
        if (pos >= head.size() || !isSpace(head[pos])) throw InputError(path, 0, std::string("bad PFM header before ") + what);
        while (pos < head.size() && isSpace(head[pos])) ++pos;
        size_t start = pos;
        while (pos < head.size() && !isSpace(head[pos])) ++pos;
        if (pos >= head.size() || start == pos) throw InputError(path, 0, std::string("truncated PFM header (missing ") + what + ")");
        return head.substr(start, pos - start);
    };
    auto integer = [&](const char* what) {
        std::string t = token(what);
        char* end = nullptr;
        errno = 0;
        long long v = std::strtoll(t.c_str(), &end, 10);
        if (*end != '\0' || errno != 0) throw InputError(path, 0, std::string("bad PFM ") + what + " '" + t + "'");
        return int64_t(v);
    };
    int64_t w = integer("width");
    int64_t h = integer("height");
    std::string st = token("scale");
    char* end = nullptr;
    double scale = std::strtod(st.c_str(), &end);
    if (*end != '\0' || !std::isfinite(scale) || scale == 0) throw InputError(path, 0, "bad PFM scale '" + st + "'");
    ++pos;  // the single white-space byte after the scale (token() stopped on it)
    checkSize(path, w, h);

    const size_t count = size_t(w) * size_t(h) * size_t(channels);
    const std::streamoff need = std::streamoff(pos) + std::streamoff(count * 4);
    if (fileSize < need)
        throw InputError(path, 0, "truncated PFM data (" + std::to_string(fileSize) + " bytes, expected " + std::to_string(need) + ")");
    std::vector<float> data(count);
    in.clear();
    in.seekg(std::streamoff(pos), std::ios::beg);
    in.read(reinterpret_cast<char*>(data.data()), std::streamsize(count * 4));
    if (!in) throw InputError(path, 0, "read error in PFM data");

    const bool fileLittle = scale < 0;
    if (fileLittle != hostIsLittleEndian()) {
        for (float& f : data) {
            unsigned char b[4];
            std::memcpy(b, &f, 4);
            std::swap(b[0], b[3]);
            std::swap(b[1], b[2]);
            std::memcpy(&f, b, 4);
        }
    }
    const float mul = float(std::fabs(scale));
    Image img(static_cast<int>(w), static_cast<int>(h));
    for (int64_t y = 0; y < h; ++y) {
        const float* row = &data[size_t(h - 1 - y) * size_t(w) * size_t(channels)];  // bottom row first
        float* out = &img.rgb[size_t(y) * size_t(w) * 3];
        for (int64_t x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) {
                float v = row[x * channels + (channels == 3 ? c : 0)];
                out[x * 3 + c] = mul == 1.0f ? v : v * mul;
            }
        }
    }
    return img;
}

void writePfm(std::FILE* f, const Image& img) {
    std::string header = "PF\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
    if (std::fwrite(header.data(), 1, header.size(), f) != header.size()) throw std::runtime_error(std::strerror(errno));
    const bool swap = !hostIsLittleEndian();
    std::vector<float> row(size_t(img.width) * 3);
    for (int y = img.height - 1; y >= 0; --y) {
        std::memcpy(row.data(), &img.rgb[size_t(y) * row.size()], row.size() * 4);
        if (swap) {
            for (float& v : row) {
                unsigned char b[4];
                std::memcpy(b, &v, 4);
                std::swap(b[0], b[3]);
                std::swap(b[1], b[2]);
                std::memcpy(&v, b, 4);
            }
        }
        if (std::fwrite(row.data(), 4, row.size(), f) != row.size()) throw std::runtime_error(std::strerror(errno));
    }
}

}  // namespace imageio
}  // namespace wmlt
