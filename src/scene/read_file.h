// A whole file into memory for the scene readers; a name ending in ".gz" is inflated
// (Debian's zlib: pbrt's .pbrt.gz and .ply.gz). Throws InputError("path: problem") when it
// cannot be opened or read, or is named .gz and is not gzip (or is truncated).
#pragma once
#include <string>

namespace wmlt {

// `what` names the file in messages ("the PLY file", "the scene file").
std::string readWholeFile(const std::string& path, const std::string& what);

}  // namespace wmlt
