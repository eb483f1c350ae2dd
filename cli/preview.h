// A picture of a filtered probe that people would rather see than read: every level as an
// equirectangular panorama, tone mapped, stacked top (level 0) to bottom (roughest).
#pragma once

#include <filesystem>

#include "probe/cube_image.h"

namespace probefilter {

void writeLevelsPreview(const std::filesystem::path& png, const probe::CubeLevels& levels);

} // namespace probefilter
