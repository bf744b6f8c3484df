// The two packets of tev's IPC protocol that wavemmlt sends (the ones pbrt-v4's display
// code sends). A packet: its whole length in bytes (uint32, these 4 bytes included), a type
// byte, then fields: a bool as one byte, strings ending in a NUL byte, int32 and float32
// values; every number little-endian.
//   CreateImage (4): grabFocus, name, width, height, channel count, channel names
//   UpdateImage (3): grabFocus, name, channel name, x, y, width, height, then the tile's
//                    values of that channel, row by row
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace wmlt {

enum class TevPacket : uint8_t { UpdateImage = 3, CreateImage = 4 };

class TevPacketWriter {
public:
    explicit TevPacketWriter(TevPacket type) : bytes_(4, 0) { put8(uint8_t(type)); }
    TevPacketWriter& put8(uint8_t v) {
        bytes_.push_back(v);
        return *this;
    }
    TevPacketWriter& putBool(bool v) { return put8(v ? 1 : 0); }
    TevPacketWriter& putString(const std::string& s) {
        bytes_.insert(bytes_.end(), s.begin(), s.end());
        return put8(0);
    }
    TevPacketWriter& put32(uint32_t v) {
        for (int i = 0; i < 4; ++i) put8(uint8_t(v >> (8 * i)));
        return *this;
    }
    TevPacketWriter& putInt(int32_t v) { return put32(uint32_t(v)); }
    TevPacketWriter& putFloat(float v) {
        uint32_t bits;
        std::memcpy(&bits, &v, 4);
        return put32(bits);
    }
    // The finished packet, its length written in front.
    std::vector<uint8_t> finish() {
        const uint32_t n = uint32_t(bytes_.size());
        for (int i = 0; i < 4; ++i) bytes_[size_t(i)] = uint8_t(n >> (8 * i));
        return std::move(bytes_);
    }

private:
    std::vector<uint8_t> bytes_;
};

}  // namespace wmlt
