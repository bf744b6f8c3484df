#include "scene/read_file.h"

#include <zlib.h>

#include <cstdio>

#include "wavemmlt/error.h"

namespace wmlt {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The members of a gzip file, inflated one after another (RFC 1952; zlib's inflate with
// gzip framing checks each member's CRC and length).
std::string gunzip(const std::string& path, const std::string& in, const std::string& what) {
    if (in.size() < 2 || (unsigned char)in[0] != 0x1f || (unsigned char)in[1] != 0x8b)
        throw InputError(path, 0, what + " is named .gz but is not gzip");
    std::string out;
    z_stream z{};
    if (inflateInit2(&z, 15 + 16) != Z_OK) throw InputError(path, 0, "cannot start zlib");
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    z.avail_in = uInt(in.size());
    char buf[1 << 16];
    int r = Z_OK;
    for (;;) {
        z.next_out = reinterpret_cast<Bytef*>(buf);
        z.avail_out = sizeof buf;
        r = inflate(&z, Z_NO_FLUSH);
        out.append(buf, sizeof buf - z.avail_out);
        if (r == Z_STREAM_END) {
            if (z.avail_in == 0) break;
            inflateReset(&z);  // another member
            continue;
        }
        if (r != Z_OK) break;
        if (z.avail_in == 0 && z.avail_out != 0) { r = Z_BUF_ERROR; break; }
    }
    inflateEnd(&z);
    if (r != Z_STREAM_END) throw InputError(path, 0, what + " is not valid gzip data (truncated or corrupt)");
    return out;
}

}  // namespace

std::string readWholeFile(const std::string& path, const std::string& what) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(path, 0, "cannot open " + what);
    std::string data;
    char buf[1 << 16];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
    const bool bad = std::ferror(f);  // a folder: EISDIR on the first read
    std::fclose(f);
    if (bad) throw InputError(path, 0, "cannot read " + what);
    return endsWith(path, ".gz") ? gunzip(path, data, what) : data;
}

}  // namespace wmlt
