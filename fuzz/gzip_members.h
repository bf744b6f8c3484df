// A fuzz input as the bytes of a .gz file (fuzz_pbrt_gz and its regression test): an input
// that starts with gzip's magic is kept as it is (truncated, corrupt and multi-member
// files reach the inflating reader), any other is compressed here, split into two gzip
// members at its middle, so that the text reaches the tokenizer across a member boundary.
#pragma once
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace fuzz {

inline void gzipMember(const uint8_t* data, size_t size, std::string& out) {
    z_stream z{};
    if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) std::abort();
    z.next_in = const_cast<Bytef*>(data);
    z.avail_in = uInt(size);
    char buf[1 << 14];
    int r;
    do {
        z.next_out = reinterpret_cast<Bytef*>(buf);
        z.avail_out = sizeof buf;
        r = deflate(&z, Z_FINISH);
        out.append(buf, sizeof buf - z.avail_out);
    } while (r == Z_OK || r == Z_BUF_ERROR);
    deflateEnd(&z);
    if (r != Z_STREAM_END) std::abort();
}

inline std::string asGzip(const uint8_t* data, size_t size) {
    if (size >= 2 && data[0] == 0x1f && data[1] == 0x8b) return std::string(reinterpret_cast<const char*>(data), size);
    std::string out;
    gzipMember(data, size / 2, out);
    gzipMember(data + size / 2, size - size / 2, out);
    return out;
}

}  // namespace fuzz
