// BC6H's layout of a cube level, shared by the encoder (probe::gpu::Bc6hEncoder) and the KTX2 writer:
// the six faces in order, each face's 4x4 blocks row by row, 16 bytes a block; a level smaller than
// 4x4 fills one block a face.
#pragma once

#include <cstddef>

namespace probe {

inline std::size_t bc6hLevelBytes(int faceSize) {
    const std::size_t across = (std::size_t(faceSize) + 3) / 4;
    return 6 * across * across * 16;
}

} // namespace probe
