// OpenEXR: reads R, G, B (a missing one reads as 0) or Y (grey) as 32-bit float whatever
// the stored type (half, float, uint); luminance-chroma files (RY, BY) go through
// RgbaInputFile. The image is the data window. Writes FLOAT R, G, B, ZIP-compressed.
// Every OpenEXR exception becomes an InputError naming the file.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <openexr.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "image/image_formats.h"
#include "wavemmlt/error.h"

namespace wmlt {
namespace imageio {

namespace {

// Rows per read: the image is read in strips and grows strip by strip, so a small file that
// claims a huge data window fails (OpenEXR throws on its missing chunks) before it has cost
// more memory than one strip (fuzz_exr). A multiple of 256 lines (the largest chunk, DWAB)
// when possible, so that no chunk is decoded twice; at most about 2^20 pixels.
int64_t stripRows(int64_t w) {
    int64_t rows = std::max<int64_t>(1, (int64_t(1) << 20) / w);
    if (rows >= 256) rows -= rows % 256;
    return rows;
}

Image readLuminanceChroma(const std::string& path) {
    Imf::RgbaInputFile file(path.c_str());
    Imath::Box2i dw = file.dataWindow();
    int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    checkSize(path, w, h);
    Image img;
    img.width = int(w);
    img.height = int(h);
    const int64_t rows = stripRows(w);
    std::vector<Imf::Rgba> px;
    for (int64_t y0 = 0; y0 < h; y0 += rows) {
        const int64_t n = std::min(rows, h - y0);
        px.assign(size_t(w) * size_t(n), Imf::Rgba(0.0f, 0.0f, 0.0f, 0.0f));
        // Imf's own base-pointer arithmetic (as Slice::Make does): pixel (x, y) of the
        // data window lands at px[(y - first) * w + (x - dw.min.x)].
        const intptr_t base =
            intptr_t(px.data()) - (intptr_t(dw.min.x) + (intptr_t(dw.min.y) + intptr_t(y0)) * intptr_t(w)) * intptr_t(sizeof(Imf::Rgba));
        file.setFrameBuffer(reinterpret_cast<Imf::Rgba*>(base), 1, size_t(w));
        file.readPixels(int(dw.min.y + y0), int(dw.min.y + y0 + n - 1));
        const size_t at = img.rgb.size();
        img.rgb.resize(at + px.size() * 3);
        for (size_t i = 0; i < px.size(); ++i) {
            img.rgb[at + 3 * i] = float(px[i].r);
            img.rgb[at + 3 * i + 1] = float(px[i].g);
            img.rgb[at + 3 * i + 2] = float(px[i].b);
        }
    }
    return img;
}

// The data window from the header alone (OpenEXRCore reads the chunk table lazily): the
// size is checked before Imf::InputFile allocates a line-offset table for the claimed
// height (8 bytes per chunk: 512 MB for a header that claims 2^30 rows).
void checkHeaderSize(const std::string& path) {
    exr_context_t ctx = nullptr;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char*) {};  // reported below
    if (exr_start_read(&ctx, path.c_str(), &init) != EXR_ERR_SUCCESS) {
        exr_finish(&ctx);
        return;  // not readable as EXR: Imf::InputFile says why
    }
    exr_attr_box2i_t box{};
    const bool ok = exr_get_data_window(ctx, 0, &box) == EXR_ERR_SUCCESS;
    exr_finish(&ctx);
    if (ok) checkSize(path, int64_t(box.max.x) - box.min.x + 1, int64_t(box.max.y) - box.min.y + 1);
}

Image readExrImpl(const std::string& path) {
    checkHeaderSize(path);
    Imf::InputFile file(path.c_str());
    const Imf::Header& hdr = file.header();
    const Imath::Box2i dw = hdr.dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    checkSize(path, w, h);
    const Imf::ChannelList& chans = hdr.channels();
    const Imf::Channel* rgb[3] = {chans.findChannel("R"), chans.findChannel("G"), chans.findChannel("B")};
    const Imf::Channel* y = chans.findChannel("Y");
    const bool hasRgb = rgb[0] || rgb[1] || rgb[2];
    if (!hasRgb && (chans.findChannel("RY") || chans.findChannel("BY"))) return readLuminanceChroma(path);
    auto fullRes = [&](const Imf::Channel* c, const char* name) {
        if (c && (c->xSampling != 1 || c->ySampling != 1)) throw InputError(path, 0, std::string("subsampled channel ") + name + " is not supported");
    };
    if (!hasRgb && !y) {
        std::string names;
        for (auto it = chans.begin(); it != chans.end(); ++it) names += std::string(names.empty() ? "" : ", ") + it.name();
        throw InputError(path, 0, "no R, G, B or Y channel (channels: " + (names.empty() ? "none" : names) + ")");
    }
    const char* names[3] = {"R", "G", "B"};
    if (hasRgb)
        for (int c = 0; c < 3; ++c) fullRes(rgb[c], names[c]);
    else fullRes(y, "Y");
    Image img;
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(h);
    const int64_t rows = stripRows(w);
    std::vector<float> strip;
    for (int64_t y0 = 0; y0 < h; y0 += rows) {
        const int64_t n = std::min(rows, h - y0);
        const Imath::V2i origin(dw.min.x, int(dw.min.y + y0));
        Imf::FrameBuffer fb;
        if (hasRgb) {
            // A channel absent from the file is filled with the slice's fill value, 0.
            strip.assign(size_t(w) * size_t(n) * 3, 0.0f);
            for (int c = 0; c < 3; ++c)
                fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, strip.data() + c, origin, w, n, 3 * sizeof(float), 3 * sizeof(float) * size_t(w)));
        } else {
            strip.assign(size_t(w) * size_t(n), 0.0f);
            fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, strip.data(), origin, w, n, sizeof(float), sizeof(float) * size_t(w)));
        }
        file.setFrameBuffer(fb);
        file.readPixels(origin.y, int(origin.y + n - 1));
        if (hasRgb) {
            img.rgb.insert(img.rgb.end(), strip.begin(), strip.end());
        } else {
            const size_t at = img.rgb.size();
            img.rgb.resize(at + strip.size() * 3);
            for (size_t i = 0; i < strip.size(); ++i) img.rgb[at + 3 * i] = img.rgb[at + 3 * i + 1] = img.rgb[at + 3 * i + 2] = strip[i];
        }
    }
    return img;
}

}  // namespace

Image readExr(const std::string& path) {
    checkReadable(path);
    try {
        return readExrImpl(path);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path, 0, std::string("cannot read OpenEXR file: ") + e.what());
    }
}

void writeExr(const std::string& tmpPath, const Image& img) {
    Imf::Header hdr(img.width, img.height);
    hdr.compression() = Imf::ZIP_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names) hdr.channels().insert(n, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(tmpPath.c_str(), hdr);
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c)
        fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, img.rgb.data() + c, Imath::V2i(0, 0), img.width, img.height, 3 * sizeof(float),
                                             3 * sizeof(float) * size_t(img.width)));
    file.setFrameBuffer(fb);
    file.writePixels(img.height);
}

}  // namespace imageio
}  // namespace wmlt
