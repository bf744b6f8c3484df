// readImage / writeImage: dispatch on the extension, the sRGB curve, PNG, JPEG and TGA through
// stb_image (Debian's libstb.so provides the implementation), the write-to-a-temporary-
// name-then-rename protocol. EXR is in exr.cpp, PFM in pfm.cpp, Radiance HDR in hdr.cpp.
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "image/image_formats.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

namespace wmlt {

// IEC 61966-2-1 (the exact piecewise curve, evaluated in double). Values below the
// linear segment's start continue the linear segment (no clamping here).
float srgbToLinear(float v) {
    double x = v;
    if (!(x > 0.04045)) return float(x / 12.92);  // also NaN -> NaN
    return float(std::pow((x + 0.055) / 1.055, 2.4));
}

float linearToSrgb(float v) {
    double x = v;
    if (!(x > 0.0031308)) return float(x * 12.92);
    return float(1.055 * std::pow(x, 1.0 / 2.4) - 0.055);
}

namespace imageio {

void checkSize(const std::string& path, int64_t w, int64_t h) {
    if (w <= 0 || h <= 0) throw InputError(path, 0, "empty image (" + std::to_string(w) + " x " + std::to_string(h) + " pixels)");
    if (w > kMaxDimension || h > kMaxDimension || w * h > kMaxPixels)
        throw InputError(path, 0, "image size " + std::to_string(w) + " x " + std::to_string(h) + " is too large (corrupt header?)");
}

void checkReadable(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw InputError(path, 0, "cannot open: is a directory");
    if (!S_ISREG(st.st_mode)) throw InputError(path, 0, "cannot open: not a regular file (a device, FIFO or socket)");
    if (::access(path.c_str(), R_OK) != 0) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
}

// The whole file, or an InputError naming the path and the system's reason.
std::string readFileBytes(const std::string& path) {
    checkReadable(path);
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
    std::string bytes;
    char buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, n);
    bool bad = std::ferror(f) != 0;
    int err = errno;
    std::fclose(f);
    if (bad) throw InputError(path, 0, std::string("read error: ") + std::strerror(err));
    return bytes;
}

}  // namespace imageio

namespace {

std::string lowerExtension(const std::string& path) {
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string stbReason() {
    const char* r = stbi_failure_reason();
    return (r && *r) ? std::string(r) : std::string("corrupt or truncated data");
}

// stb_image 2.27 (Debian 12) mishandles JPEG tables in three ways (all found by
// fuzz/fuzz_jpeg): it writes past its Huffman size table (257 entries) when a DHT table
// declares more than 256 codes, and it decodes a scan with a Huffman table no DHT defined,
// or dequantises with a quantisation table no DQT defined, whose memory it never
// initialised (an index out of bounds, or a signed overflow, that depends on what the
// allocator returned). Walk the marker segments and refuse these before stb_image sees
// them. Anything else malformed is left to stb_image, which reports it.
void checkJpegTables(const std::string& path, const unsigned char* d, size_t size) {
    if (size < 4 || d[0] != 0xFF || d[1] != 0xD8) return;
    auto byte = [&](size_t i) { return i < size ? d[i] : 0; };  // past the end: 0, as stb_image reads
    bool progressive = false;
    unsigned huffman[2] = {0, 0};        // per class (0 DC, 1 AC): a bit per table id 0-3 a DHT defined
    unsigned quant = 0, frameQuant = 0;  // the quantisation tables DQTs defined; the frame's components use
    auto undefined = [&](const std::string& what) {
        throw InputError(path, 0, "corrupt JPEG data (a scan uses " + what + ", which no segment before it defines)");
    };
    auto require = [&](int cls, int id) {
        if (id <= 3 && !(huffman[cls] >> id & 1)) undefined(std::string("Huffman table ") + (cls ? "AC " : "DC ") + std::to_string(id));
    };
    size_t pos = 2;
    while (pos + 1 < size) {
        if (d[pos] != 0xFF) {  // entropy-coded data after SOS: skip to the next marker
            ++pos;
            continue;
        }
        while (pos < size && d[pos] == 0xFF) ++pos;  // fill bytes
        if (pos >= size) return;
        const unsigned char m = d[pos++];
        if (m == 0x00 || m == 0x01 || (m >= 0xD0 && m <= 0xD8)) continue;  // stuffed 0, TEM, RSTn, SOI
        if (m == 0xD9) return;                                             // EOI
        if (pos + 2 > size) return;
        const size_t len = (size_t(d[pos]) << 8) | d[pos + 1];
        if (len < 2) return;
        if (m == 0xC0 || m == 0xC1 || m == 0xC2) {  // SOF0-2: components (id, sampling, quantisation table)
            progressive = m == 0xC2;
            frameQuant = 0;
            for (size_t c = 0, nc = byte(pos + 7); c < nc; ++c) {
                const int tq = byte(pos + 10 + 3 * c);
                if (tq <= 3) frameQuant |= 1u << tq;
            }
        }
        if (m == 0xDB)  // DQT: tables of (precision/id, 64 or 128 bytes)
            for (size_t q = pos + 2; q < pos + len && q < size; q += 1 + 64 * ((byte(q) >> 4) ? 2 : 1))
                if ((byte(q) & 15) <= 3) quant |= 1u << (byte(q) & 15);
        if (m == 0xC4) {  // DHT: tables of (class/id, 16 counts, values)
            // As stb_image reads it: whole tables while the declared length lasts.
            for (size_t q = pos + 2; q < pos + len && q < size;) {
                size_t n = 0;
                for (int i = 0; i < 16; ++i) n += byte(q + 1 + i);
                if (n > 256) throw InputError(path, 0, "corrupt JPEG data (a Huffman table declares " + std::to_string(n) + " codes, at most 256)");
                const int cls = byte(q) >> 4, id = byte(q) & 15;
                if (cls <= 1 && id <= 3) huffman[cls] |= 1u << id;
                q += 17 + n;
            }
        }
        if (m == 0xDA) {  // SOS: components (id, DC/AC table), then Ss, Se, Ah/Al
            if (const unsigned missing = frameQuant & ~quant) undefined("quantisation table " + std::to_string(__builtin_ctz(missing)));
            const size_t ns = byte(pos + 2), after = pos + 3 + 2 * ns;
            const int ss = byte(after), ah = byte(after + 2) >> 4;
            for (size_t c = 0; c < ns; ++c) {
                const int tables = byte(pos + 4 + 2 * c);
                // Baseline decodes with both; a progressive DC scan with its DC table in
                // the first pass only, an AC scan with its AC table.
                if (!progressive || (ss == 0 && ah == 0)) require(0, tables >> 4);
                if (!progressive || ss > 0) require(1, tables & 15);
            }
        }
        pos += len;
    }
}

// PNG and JPEG (8 or 16 bits, 1-4 channels; alpha is ignored): sRGB -> linear RGB.
Image readStb(const std::string& path, const char* format) {
    std::string bytes = imageio::readFileBytes(path);
    if (bytes.empty()) throw InputError(path, 0, "empty file");
    if (bytes.size() > size_t(INT32_MAX)) throw InputError(path, 0, "file too large");
    auto data = reinterpret_cast<const stbi_uc*>(bytes.data());
    int len = int(bytes.size());
    int w = 0, h = 0, comp = 0;
    // PNG: check IHDR's size ourselves (stb_image refuses huge images too, but then
    // reports "unknown image type").
    if (bytes.size() >= 24 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 && bytes.compare(12, 4, "IHDR") == 0) {
        auto be32 = [&](size_t o) {
            return (uint32_t(data[o]) << 24) | (uint32_t(data[o + 1]) << 16) | (uint32_t(data[o + 2]) << 8) | uint32_t(data[o + 3]);
        };
        imageio::checkSize(path, be32(16), be32(20));
    }
    // stb_image picks the decoder from the data, not the name: a ".png" holding a GIF, PSD,
    // TGA, BMP or PIC would reach stb's other decoders. Only the named format is read.
    const bool jpeg = std::string(format) == "JPEG", tga = std::string(format) == "TGA";
    if (tga) {
        // TGA has no signature: its header's colour-map type (0 or 1) and image type
        // (1-3 plain, 9-11 run-length) tell it from every other format stb_image reads
        // (whose first two bytes are never such a pair).
        const int mapType = bytes.size() > 2 ? data[1] : -1, type = bytes.size() > 2 ? data[2] : -1;
        if (bytes.size() < 18 || mapType > 1 || !((type >= 1 && type <= 3) || (type >= 9 && type <= 11)))
            throw InputError(path, 0, "not a TGA file (its header's colour-map and image types are not TGA's)");
    } else if (jpeg ? bytes.compare(0, 3, "\xFF\xD8\xFF") != 0 : bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) {
        throw InputError(path, 0, std::string("not a ") + format + " file (no " + format + " signature)");
    }
    if (jpeg) checkJpegTables(path, data, bytes.size());
    if (!stbi_info_from_memory(data, len, &w, &h, &comp))
        throw InputError(path, 0, std::string("not a readable ") + format + " file (" + stbReason() + ")");
    imageio::checkSize(path, w, h);
    if (tga) {  // the pixels must be in the file (stb_image would decode a huge image from a few bytes)
        auto le16 = [&](size_t o) { return uint64_t(data[o]) | (uint64_t(data[o + 1]) << 8); };
        const uint64_t pixelBytes = (uint64_t(data[16]) + 7) / 8, pixels = uint64_t(w) * uint64_t(h);
        const uint64_t map = data[1] ? le16(5) * ((uint64_t(data[7]) + 7) / 8) : 0;
        const uint64_t body = data[2] >= 9 ? (pixels + 127) / 128 * (1 + pixelBytes) : pixels * pixelBytes;
        const uint64_t need = 18 + uint64_t(data[0]) + map + body;
        if (bytes.size() < need)
            throw InputError(path, 0,
                             "the file holds " + std::to_string(bytes.size()) + " bytes, fewer than its " + std::to_string(w) + " x " +
                                 std::to_string(h) + " pixels need (" + std::to_string(need) + ")");
    }
    Image img;  // allocated once stb_image has decoded the data (a header alone proves little)
    size_t n = 0;
    auto toRgb = [&](auto* px, int c, auto lin) {
        img = Image(w, h);
        n = size_t(w) * size_t(h);
        for (size_t i = 0; i < n; ++i) {
            const auto* p = px + i * size_t(c);
            float r, g, b;
            if (c <= 2) r = g = b = lin(p[0]);
            else {
                r = lin(p[0]);
                g = lin(p[1]);
                b = lin(p[2]);
            }
            img.rgb[3 * i] = r;
            img.rgb[3 * i + 1] = g;
            img.rgb[3 * i + 2] = b;
        }
    };
    if (stbi_is_16_bit_from_memory(data, len)) {
        stbi_us* px = stbi_load_16_from_memory(data, len, &w, &h, &comp, 0);
        if (!px) throw InputError(path, 0, std::string("cannot decode ") + format + " data (" + stbReason() + ")");
        toRgb(px, comp, [](stbi_us v) { return srgbToLinear(float(v) / 65535.0f); });
        stbi_image_free(px);
    } else {
        stbi_uc* px = stbi_load_from_memory(data, len, &w, &h, &comp, 0);
        if (!px) throw InputError(path, 0, std::string("cannot decode ") + format + " data (" + stbReason() + ")");
        static const auto lut = [] {
            std::vector<float> t(256);
            for (int i = 0; i < 256; ++i) t[i] = srgbToLinear(float(i) / 255.0f);
            return t;
        }();
        toRgb(px, comp, [](stbi_uc v) { return lut[v]; });
        stbi_image_free(px);
    }
    return img;
}

struct WriteSink {
    std::FILE* f;
    bool failed = false;
};

void writePng(std::FILE* f, const Image& img, float exposure) {
    const std::vector<unsigned char> bytes = toSrgb8(img, exposure);
    WriteSink sink{f};
    auto write = [](void* ctx, void* data, int size) {
        auto* s = static_cast<WriteSink*>(ctx);
        if (std::fwrite(data, 1, size_t(size), s->f) != size_t(size)) s->failed = true;
    };
    if (!stbi_write_png_to_func(write, &sink, img.width, img.height, 3, bytes.data(), img.width * 3)) throw std::runtime_error("PNG encoder failed");
    if (sink.failed) throw std::runtime_error(std::strerror(errno));
}

}  // namespace

std::vector<unsigned char> toSrgb8(const Image& img, float exposure) {
    const float scale = std::exp2(exposure);
    std::vector<unsigned char> bytes(img.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
        float s = linearToSrgb(img.rgb[i] * scale);
        if (!(s > 0)) s = 0;  // also NaN
        if (s > 1) s = 1;
        bytes[i] = static_cast<unsigned char>(s * 255.0f + 0.5f);
    }
    return bytes;
}

bool isWritableImageExtension(const std::string& path) {
    std::string ext = lowerExtension(path);
    return ext == ".exr" || ext == ".pfm" || ext == ".png";
}

Image readImage(const std::string& path) {
    std::string ext = lowerExtension(path);
    if (ext == ".exr") return imageio::readExr(path);
    if (ext == ".pfm") return imageio::readPfm(path);
    if (ext == ".hdr" || ext == ".rgbe" || ext == ".pic") return imageio::readHdr(path);
    if (ext == ".png") return readStb(path, "PNG");
    if (ext == ".jpg" || ext == ".jpeg") return readStb(path, "JPEG");
    if (ext == ".tga") return readStb(path, "TGA");
    throw InputError(path, 0, "unknown image extension '" + ext + "' (readable: .exr, .pfm, .hdr, .png, .jpg, .jpeg, .tga)");
}

void writeImage(const std::string& path, const Image& image, float exposure) {
    std::string ext = lowerExtension(path);
    if (!isWritableImageExtension(path))
        throw InputError(path, 0, "cannot write: unknown image extension '" + ext + "' (writable: .exr, .pfm, .png)");
    if (image.width <= 0 || image.height <= 0 || image.rgb.size() != size_t(image.width) * size_t(image.height) * 3)
        throw InputError(path, 0,
                         "cannot write an empty or malformed image (" + std::to_string(image.width) + " x " + std::to_string(image.height) + ")");
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw InputError("cannot write " + path + ": " + std::strerror(errno));
    try {
        if (ext == ".png") {
            writePng(f, image, exposure);
        } else if (ext == ".pfm") {
            imageio::writePfm(f, image);
        } else {  // .exr: OpenEXR opens the (already created) temporary file itself
            std::fclose(f);
            f = nullptr;
            imageio::writeExr(tmp, image);
        }
        if (f) {
            errno = 0;
            bool bad = std::fflush(f) != 0 || std::ferror(f) != 0;
            int err = errno;
            if (std::fclose(f) != 0 && !bad) {
                bad = true;
                err = errno;
            }
            f = nullptr;
            if (bad) throw std::runtime_error(err ? std::strerror(err) : "write error");
        }
        if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error(std::strerror(errno));
    } catch (const std::exception& e) {
        if (f) std::fclose(f);
        std::remove(tmp.c_str());
        throw InputError("cannot write " + path + ": " + e.what());
    }
}

}  // namespace wmlt
