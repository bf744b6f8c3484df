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

#include <stdexcept>

#include "image/image_formats.h"
#include "wavemmlt/error.h"

namespace wmlt {
namespace imageio {

namespace {

Image readLuminanceChroma(const std::string& path) {
    Imf::RgbaInputFile file(path.c_str());
    Imath::Box2i dw = file.dataWindow();
    int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    checkSize(path, w, h);
    std::vector<Imf::Rgba> px(size_t(w) * size_t(h));
    file.setFrameBuffer(px.data() - dw.min.x - int64_t(dw.min.y) * w, 1, size_t(w));
    file.readPixels(dw.min.y, dw.max.y);
    Image img(static_cast<int>(w), static_cast<int>(h));
    for (size_t i = 0; i < px.size(); ++i) {
        img.rgb[3 * i] = float(px[i].r);
        img.rgb[3 * i + 1] = float(px[i].g);
        img.rgb[3 * i + 2] = float(px[i].b);
    }
    return img;
}

Image readExrImpl(const std::string& path) {
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
        if (c && (c->xSampling != 1 || c->ySampling != 1))
            throw InputError(path, 0, std::string("subsampled channel ") + name + " is not supported");
    };
    Image img(static_cast<int>(w), static_cast<int>(h));
    Imf::FrameBuffer fb;
    if (hasRgb) {
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) {
            fullRes(rgb[c], names[c]);
            // A channel absent from the file is filled with the slice's fill value, 0.
            fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, img.rgb.data() + c, dw, 3 * sizeof(float),
                                                 3 * sizeof(float) * size_t(w)));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return img;
    }
    if (!y) {
        std::string names;
        for (auto it = chans.begin(); it != chans.end(); ++it) names += std::string(names.empty() ? "" : ", ") + it.name();
        throw InputError(path, 0, "no R, G, B or Y channel (channels: " + (names.empty() ? "none" : names) + ")");
    }
    fullRes(y, "Y");
    std::vector<float> grey(size_t(w) * size_t(h));
    fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, grey.data(), dw, sizeof(float), sizeof(float) * size_t(w)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (size_t i = 0; i < grey.size(); ++i) img.rgb[3 * i] = img.rgb[3 * i + 1] = img.rgb[3 * i + 2] = grey[i];
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
        fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, img.rgb.data() + c, Imath::V2i(0, 0), img.width,
                                             img.height, 3 * sizeof(float), 3 * sizeof(float) * size_t(img.width)));
    file.setFrameBuffer(fb);
    file.writePixels(img.height);
}

}  // namespace imageio
}  // namespace wmlt
