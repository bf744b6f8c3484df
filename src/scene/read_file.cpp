#include "scene/read_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include "wavemmlt/error.h"

namespace wmlt {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

const char* kindOf(mode_t m) {
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISFIFO(m)) return "a FIFO (a pipe)";
    if (S_ISSOCK(m)) return "a socket";
    return "not a plain file";
}

}  // namespace

std::string regularFileProblem(const std::string& path, const std::string& what) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return "cannot open " + what + (errno == ENOENT ? std::string() : std::string(": ") + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) return "cannot read " + what + ": it is a folder";
    if (!S_ISREG(st.st_mode)) return what + " is not a regular file (" + kindOf(st.st_mode) + "; it may never end)";
    return "";
}

void requireRegularFile(const std::string& path, const std::string& what) {
    if (const std::string why = regularFileProblem(path, what); !why.empty()) throw InputError(path, 0, why);
}

FileStream::FileStream(const std::string& path, const std::string& what) : path_(path), what_(what) {
    requireRegularFile(path, what);
    f_ = std::fopen(path.c_str(), "rb");
    if (!f_) throw InputError(path, 0, "cannot open " + what + ": " + std::strerror(errno));
    struct stat st;
    if (::fstat(fileno(f_), &st) == 0) fileBytes_ = uint64_t(st.st_size);
    gzip_ = endsWith(path, ".gz");
    if (gzip_) {
        unsigned char magic[2] = {0, 0};
        const size_t n = readRaw(reinterpret_cast<char*>(magic), 2);
        if (n < 2 || magic[0] != 0x1f || magic[1] != 0x8b) {
            std::fclose(f_);
            f_ = nullptr;
            throw InputError(path, 0, what + " is named .gz but is not gzip");
        }
        if (inflateInit2(&z_, 15 + 16) != Z_OK) {
            std::fclose(f_);
            f_ = nullptr;
            throw InputError(path, 0, "cannot start zlib");
        }
        zOpen_ = true;
        std::memcpy(in_, magic, 2);
        z_.next_in = reinterpret_cast<Bytef*>(in_);
        z_.avail_in = 2;
    }
}

FileStream::~FileStream() {
    if (zOpen_) inflateEnd(&z_);
    if (f_) std::fclose(f_);
}

size_t FileStream::readRaw(char* out, size_t n) {
    const size_t got = std::fread(out, 1, n, f_);
    if (got == 0 && std::ferror(f_)) throw InputError(path_, 0, "cannot read " + what_ + ": " + std::strerror(errno));
    return got;
}

size_t FileStream::read(char* out, size_t n) {
    if (!gzip_) {
        const size_t got = n ? readRaw(out, n) : 0;
        total_ += got;
        return got;
    }
    if (zEnd_ || n == 0) return 0;
    z_.next_out = reinterpret_cast<Bytef*>(out);
    z_.avail_out = uInt(std::min<size_t>(n, 1u << 30));
    const uInt asked = z_.avail_out;
    while (z_.avail_out == asked) {  // until some output or the end
        if (z_.avail_in == 0) {
            const size_t got = readRaw(in_, sizeof in_);
            if (got == 0) {
                throw InputError(path_, 0,
                                 what_ + " is not valid gzip data (truncated: the file ends inside a member, after " + std::to_string(total_) +
                                     " inflated bytes)");
            }
            z_.next_in = reinterpret_cast<Bytef*>(in_);
            z_.avail_in = uInt(got);
        }
        const int r = inflate(&z_, Z_NO_FLUSH);
        if (r == Z_STREAM_END) {
            // Another member may follow (RFC 1952); trailing bytes that are not one are an error.
            if (z_.avail_in == 0) {
                const size_t got = readRaw(in_, sizeof in_);
                z_.next_in = reinterpret_cast<Bytef*>(in_);
                z_.avail_in = uInt(got);
            }
            if (z_.avail_in == 0) {
                zEnd_ = true;
                break;
            }
            inflateReset(&z_);
            continue;
        }
        if (r != Z_OK && r != Z_BUF_ERROR)
            throw InputError(path_, 0, what_ + " is not valid gzip data (corrupt after " + std::to_string(total_) + " inflated bytes)");
    }
    const size_t got = asked - z_.avail_out;
    total_ += got;
    return got;
}

std::string readUntil(FileStream& in, std::string_view marker, size_t limit) {
    std::string data;
    char buf[4096];
    size_t searched = 0;
    while (data.size() < limit) {
        const size_t n = in.read(buf, std::min(sizeof buf, limit - data.size()));
        if (n == 0) break;
        data.append(buf, n);
        const size_t from = searched > marker.size() + 2 ? searched - marker.size() - 2 : 0;
        for (size_t at = data.find(marker, from); at != std::string::npos; at = data.find(marker, at + 1)) {
            size_t e = at + marker.size();
            while (e < data.size() && (data[e] == ' ' || data[e] == '\t' || data[e] == '\r')) ++e;
            if (e < data.size() && data[e] == '\n' && (at == 0 || data[at - 1] == '\n')) return data;
        }
        searched = data.size();
    }
    return data;
}

void readRest(FileStream& in, std::string& data) {
    char buf[1 << 16];
    for (size_t n; (n = in.read(buf, sizeof buf)) > 0;) data.append(buf, n);
}

Image readSceneImage(const std::string& path) {
    Image img = readImage(path);  // (which refuses what is not a regular file)
    for (size_t i = 0; i < img.rgb.size(); ++i)
        if (!std::isfinite(img.rgb[i])) {
            const size_t px = i / 3;
            throw InputError(path, 0,
                             "pixel (" + std::to_string(px % size_t(img.width)) + ", " + std::to_string(px / size_t(img.width)) + ") is " +
                                 (std::isnan(img.rgb[i]) ? "NaN" : "infinite"));
        }
    return img;
}

std::string readWholeFile(const std::string& path, const std::string& what) {
    FileStream in(path, what);
    std::string data;
    if (!in.gzip()) data.reserve(size_t(in.fileBytes()));
    readRest(in, data);
    return data;
}

}  // namespace wmlt
