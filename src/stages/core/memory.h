// The machine's physical memory, for refusing renders that would not fit before they start.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <string>

namespace wmlt {

// Bytes of physical memory (0 when unknown).
inline double physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? double(pages) * double(size) : 0;
}

// "123 MiB", "4.5 GiB": a size for messages.
inline std::string bytesText(double b) {
    const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int u = 0;
    while (b >= 1024 && u < 6) {
        b /= 1024;
        ++u;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", b, units[u]);
    return buf;
}

}  // namespace wmlt
