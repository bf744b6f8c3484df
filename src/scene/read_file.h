// Reading the files a scene names, in bounded memory: a regular file only (a device such as
// /dev/zero, a FIFO or a socket never ends, a folder cannot be read), read in chunks, and a
// name ending in ".gz" inflated as it is read (Debian's zlib: pbrt's .pbrt.gz and .ply.gz),
// so a reader that stops at its first bad byte never inflates the rest of a gzip bomb.
// Every problem is an InputError("path: problem").
#pragma once
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "wavemmlt/image.h"

namespace wmlt {

// Throws InputError(path, 0, ...) unless `path` is a regular file that can be opened
// ("cannot open <what>", "cannot read <what>: a folder", "<what> is not a regular file
// (a character device: /dev/zero?)"). `what` names the file ("the PLY file").
void requireRegularFile(const std::string& path, const std::string& what);
// The same problem as text without the path ("" when there is none), for readers that report
// their own way (a spectrum file).
std::string regularFileProblem(const std::string& path, const std::string& what);

// A file's bytes in order, inflated when its name ends in ".gz" (every gzip member, each
// member's CRC and length checked). read() returns 0 only at the end.
class FileStream {
public:
    FileStream(const std::string& path, const std::string& what);  // requireRegularFile, then open
    ~FileStream();
    FileStream(const FileStream&) = delete;
    FileStream& operator=(const FileStream&) = delete;

    size_t read(char* out, size_t n);             // up to n bytes; 0 at the end of the (inflated) data
    uint64_t consumed() const { return total_; }  // bytes returned so far
    bool gzip() const { return gzip_; }
    uint64_t fileBytes() const { return fileBytes_; }  // the size on disk

private:
    size_t readRaw(char* out, size_t n);
    std::string path_, what_;
    std::FILE* f_ = nullptr;
    bool gzip_ = false, zOpen_ = false, zEnd_ = false;
    z_stream z_{};
    char in_[1 << 16];
    uint64_t total_ = 0, fileBytes_ = 0;
};

// The bytes of `in` up to and including the first occurrence of `marker` followed by a
// line break, or up to `limit` bytes or the end, whichever comes first (a PLY header).
std::string readUntil(FileStream& in, std::string_view marker, size_t limit);
// The rest of `in`, appended to `data`.
void readRest(FileStream& in, std::string& data);

// An image a scene reads (texture, environment map, emission image): readImage, and then
// every pixel must be finite ("path: pixel (x, y) is NaN"): one NaN or infinite texel
// would poison every sample that sees it. The same rule for every format's importer.
Image readSceneImage(const std::string& path);

// A whole file into memory (FileStream's checks); for files whose readers need it whole.
std::string readWholeFile(const std::string& path, const std::string& what);

}  // namespace wmlt
