// wavemmlt-img: compare, convert and inspect images (EXR, PFM, HDR, PNG, JPEG).
// Exit status: 0 success, 2 bad input (unreadable file, size mismatch, bad arguments),
// 1 an internal error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "image/compare.h"
#include "wavemmlt/error.h"
#include "wavemmlt/image.h"

using namespace wmlt;

namespace {

constexpr double kMaskFraction = 0.01;

const char* kHelp =
    "usage: wavemmlt-img <command> [arguments]\n"
    "\n"
    "Commands:\n"
    "  diff A B [--mask OUT.png] [--json]\n"
    "      Compare image A with the reference B (same size). Prints, over all pixels and\n"
    "      the three channels (PNG/JPEG are linearised first):\n"
    "        rmse     sqrt(mean((a - b)^2))\n"
    "        relmse   mean((a - b)^2 / (b^2 + 1e-2))   (relative MSE, epsilon 1e-2)\n"
    "        mae      mean(|a - b|)\n"
    "        max_abs  max |a - b|\n"
    "      Values where a or b is NaN or infinite are left out of the means and counted\n"
    "      as 'nonfinite'. --mask writes a picture of where the images differ most:\n"
    "      white for the top 1% of pixels by squared error (sum over channels), a grey\n"
    "      ramp (proportional to the error's square root) below, black where equal.\n"
    "  convert A B [--exposure E]\n"
    "      Read A (.exr .pfm .hdr .png .jpg .jpeg) and write B (.exr .pfm .png),\n"
    "      multiplying by 2^E first (default 0). PNG output is 8-bit sRGB, clamped.\n"
    "  info A [--json]\n"
    "      Size, per-channel min / max / mean over the finite values, and the number\n"
    "      of NaN and infinite values.\n"
    "  --help\n"
    "      This text.\n"
    "\n"
    "Exit status: 0 success, 2 bad input (unreadable file, different sizes, bad arguments).\n";

struct UsageError : std::exception {
    std::string msg;
    explicit UsageError(std::string m) : msg(std::move(m)) {}
    const char* what() const noexcept override { return msg.c_str(); }
};

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        unsigned char u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            out += buf;
        } else out += c;
    }
    return out + "\"";
}

std::string num(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

struct Args {
    std::vector<std::string> positional;
    std::string mask;
    bool json = false;
    bool hasExposure = false;
    float exposure = 0;
};

Args parseArgs(int argc, char** argv, int first) {
    Args a;
    for (int i = first; i < argc; ++i) {
        std::string s = argv[i];
        if (s == "--json") {
            a.json = true;
        } else if (s == "--mask" || s == "--exposure") {
            if (i + 1 >= argc) throw UsageError(s + " needs a value");
            std::string v = argv[++i];
            if (s == "--mask") {
                a.mask = v;
            } else {
                char* end = nullptr;
                double e = std::strtod(v.c_str(), &end);
                if (v.empty() || *end != '\0' || !std::isfinite(e)) throw UsageError("bad --exposure value '" + v + "'");
                a.exposure = float(e);
                a.hasExposure = true;
            }
        } else if (s.size() > 1 && s[0] == '-' && !(s[1] >= '0' && s[1] <= '9') && s[1] != '.') {
            throw UsageError("unknown option '" + s + "'");
        } else {
            a.positional.push_back(s);
        }
    }
    return a;
}

void expectPositional(const Args& a, size_t n, const char* cmd) {
    if (a.positional.size() != n)
        throw UsageError(std::string(cmd) + " takes " + std::to_string(n) + " file name" + (n > 1 ? "s" : "") + ", got " +
                         std::to_string(a.positional.size()));
}

int cmdDiff(const Args& args) {
    expectPositional(args, 2, "diff");
    if (args.hasExposure) throw UsageError("diff does not take --exposure");
    const std::string &pa = args.positional[0], &pb = args.positional[1];
    if (!args.mask.empty() && !isWritableImageExtension(args.mask))
        throw InputError(args.mask, 0, "cannot write: unknown image extension (writable: .exr, .pfm, .png)");
    Image a = readImage(pa), b = readImage(pb);
    if (a.width != b.width || a.height != b.height)
        throw InputError("size mismatch: " + pa + " is " + std::to_string(a.width) + " x " + std::to_string(a.height) + ", " + pb + " is " +
                         std::to_string(b.width) + " x " + std::to_string(b.height));
    const size_t nPix = size_t(a.width) * size_t(a.height);
    std::vector<double> pixelErr;
    const ImageDiff d = diffImages(a, b, &pixelErr);
    const double rmse = d.rmse, relmse = d.relmse, mae = d.mae, maxAbs = d.maxAbs;
    const size_t nonFinite = d.nonFinite;

    if (!args.mask.empty()) {
        std::vector<double> sorted = pixelErr;
        const size_t k = std::max<size_t>(1, size_t(std::ceil(kMaskFraction * double(nPix))));
        std::nth_element(sorted.begin(), sorted.begin() + (nPix - k), sorted.end());
        const double thr = sorted[nPix - k];
        Image mask(a.width, a.height);
        for (size_t i = 0; i < nPix; ++i) {
            const double e = pixelErr[i];
            float g;  // display (sRGB) value
            if (!(e > 0)) g = 0.0f;
            else if (e >= thr) g = 1.0f;
            else g = float(0.75 * std::sqrt(e / thr));
            const float lin = srgbToLinear(g);
            mask.rgb[3 * i] = mask.rgb[3 * i + 1] = mask.rgb[3 * i + 2] = lin;
        }
        writeImage(args.mask, mask);
    }

    if (args.json) {
        std::printf(
            "{\"a\": %s, \"b\": %s, \"width\": %d, \"height\": %d, \"rmse\": %s, \"relmse\": %s, "
            "\"relmse_epsilon\": %s, \"mae\": %s, \"max_abs\": %s, \"nonfinite\": %zu}\n",
            jsonString(pa).c_str(), jsonString(pb).c_str(), a.width, a.height, num(rmse).c_str(), num(relmse).c_str(), num(kRelMseEpsilon).c_str(),
            num(mae).c_str(), num(maxAbs).c_str(), nonFinite);
    } else {
        std::printf("size      %d x %d\n", a.width, a.height);
        std::printf("rmse      %s\n", num(rmse).c_str());
        std::printf("relmse    %s\n", num(relmse).c_str());
        std::printf("mae       %s\n", num(mae).c_str());
        std::printf("max_abs   %s\n", num(maxAbs).c_str());
        std::printf("nonfinite %zu\n", nonFinite);
        if (!args.mask.empty()) std::printf("mask      %s\n", args.mask.c_str());
    }
    return 0;
}

int cmdConvert(const Args& args) {
    expectPositional(args, 2, "convert");
    if (args.json || !args.mask.empty()) throw UsageError("convert takes only --exposure");
    const std::string &in = args.positional[0], &out = args.positional[1];
    if (!isWritableImageExtension(out)) throw InputError(out, 0, "cannot write: unknown image extension (writable: .exr, .pfm, .png)");
    Image img = readImage(in);
    if (args.exposure != 0) {
        const float s = std::exp2(args.exposure);
        for (float& v : img.rgb) v *= s;
    }
    writeImage(out, img);
    return 0;
}

int cmdInfo(const Args& args) {
    expectPositional(args, 1, "info");
    if (args.hasExposure || !args.mask.empty()) throw UsageError("info takes only --json");
    const std::string& path = args.positional[0];
    Image img = readImage(path);
    double mn[3], mx[3], sum[3];
    size_t cnt[3] = {0, 0, 0}, nan = 0, inf = 0;
    for (int c = 0; c < 3; ++c) {
        mn[c] = INFINITY;
        mx[c] = -INFINITY;
        sum[c] = 0;
    }
    for (size_t i = 0; i < img.rgb.size(); ++i) {
        const float v = img.rgb[i];
        const int c = int(i % 3);
        if (std::isnan(v)) {
            ++nan;
            continue;
        }
        if (std::isinf(v)) {
            ++inf;
            continue;
        }
        mn[c] = std::min(mn[c], double(v));
        mx[c] = std::max(mx[c], double(v));
        sum[c] += v;
        ++cnt[c];
    }
    const char* names[3] = {"R", "G", "B"};
    if (args.json) {
        std::printf("{\"file\": %s, \"width\": %d, \"height\": %d, \"channels\": {", jsonString(path).c_str(), img.width, img.height);
        for (int c = 0; c < 3; ++c)
            std::printf("%s\"%s\": {\"min\": %s, \"max\": %s, \"mean\": %s}", c ? ", " : "", names[c], num(cnt[c] ? mn[c] : NAN).c_str(),
                        num(cnt[c] ? mx[c] : NAN).c_str(), num(cnt[c] ? sum[c] / double(cnt[c]) : NAN).c_str());
        std::printf("}, \"nan\": %zu, \"inf\": %zu}\n", nan, inf);
    } else {
        std::printf("file      %s\n", path.c_str());
        std::printf("size      %d x %d\n", img.width, img.height);
        std::printf("channel   min              max              mean\n");
        for (int c = 0; c < 3; ++c)
            std::printf("%-9s %-16s %-16s %s\n", names[c], num(cnt[c] ? mn[c] : NAN).c_str(), num(cnt[c] ? mx[c] : NAN).c_str(),
                        num(cnt[c] ? sum[c] / double(cnt[c]) : NAN).c_str());
        std::printf("nan       %zu\n", nan);
        std::printf("inf       %zu\n", inf);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc < 2) throw UsageError("missing command");
        const std::string cmd = argv[1];
        if (cmd == "--help" || cmd == "-h" || cmd == "help") {
            std::fputs(kHelp, stdout);
            return 0;
        }
        for (int i = 2; i < argc; ++i)
            if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
                std::fputs(kHelp, stdout);
                return 0;
            }
        Args args = parseArgs(argc, argv, 2);
        if (cmd == "diff") return cmdDiff(args);
        if (cmd == "convert") return cmdConvert(args);
        if (cmd == "info") return cmdInfo(args);
        throw UsageError("unknown command '" + cmd + "'");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "wavemmlt-img: %s (see wavemmlt-img --help)\n", e.what());
        return 2;
    } catch (const InputError& e) {
        std::fprintf(stderr, "wavemmlt-img: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "wavemmlt-img: internal error: %s\n", e.what());
        return 1;
    }
}
