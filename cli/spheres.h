// Sphere pictures: scene materials as the renderer shades them, rendered and tone mapped.
#pragma once

#include <filesystem>
#include <vector>

#include "probe/runtime.h"
#include "probe/scene.h"

namespace probefilter {

// A scene material for the renderer: the filtered level its roughness reads under the mapping.
probe::gpu::SphereMaterial sphereMaterial(const probe::SceneMaterial& material, const probe::RoughnessMapping& mapping, int levelCount);

// Renders the spheres (probe::gpu::renderSpheres) and writes them as a PNG, exposed for the
// probe's own brightness. Returns the linear image.
probe::Image writeSpheres(const std::filesystem::path& png, const probe::gpu::Device& device, const probe::gpu::SphereScene& scene);

} // namespace probefilter
