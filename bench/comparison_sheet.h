// The comparison sheet of `probefilter compare`, laid out like the talks' figures: one row per
// method, the reference first; each row its label, its spheres and, for every method but the
// reference, a heat map of its per-pixel error against the reference's spheres.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "probe/cube_image.h"

namespace probefilter {

struct SheetRow {
    std::string label;
    probe::Image spheres; // linear RGB, the same size in every row
};

// Per pixel: sum_c |image - reference| / sum_c reference (0 where the reference is black), the
// relative error that the heat maps show.
std::vector<float> relativeError(const probe::Image& image, const probe::Image& reference);

// The image L1 of the spheres: sum |image - reference| / sum |reference| over pixels and channels.
double spheresL1(const probe::Image& image, const probe::Image& reference);

// Writes the sheet as a PNG: rows[0] is the reference. Spheres are tone mapped with `exposure`;
// heat maps go from black (0) through red to white (at `maxError`, and above), with a legend.
void writeComparisonSheet(const std::filesystem::path& png, const std::vector<SheetRow>& rows, float exposure, double maxError);

} // namespace probefilter
