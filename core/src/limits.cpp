#include "probe/limits.h"

#include <fmt/format.h>

#include "probe/cube_image.h"
#include "probe/error.h"

namespace probe {

void checkRepeat(int repeat) {
    if (repeat < 1 || repeat > kMaxRepeat) throw ParameterError("repeat", fmt::format("{}: must be 1 to {}", repeat, kMaxRepeat));
}

std::string imageSizeProblem(std::int64_t width, std::int64_t height) {
    if (width < 1 || height < 1) return fmt::format("image has zero size ({} x {})", width, height);
    if (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImagePixels)
        return fmt::format("{} x {} pixels is over the limit of {} pixels ({} per side)", width, height, kMaxImagePixels, kMaxImageSide);
    if (!layoutOfShape(width, height)) return fmt::format("wrong aspect ratio {}x{}: expected {}", width, height, kProbeShapes);
    return {};
}

} // namespace probe
