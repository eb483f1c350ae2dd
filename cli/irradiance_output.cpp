#include "irradiance_output.h"

#include <algorithm>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/irradiance.h"
#include "probe/probe_io.h"
#include "report.h"

namespace probefilter {

IrradianceOutput parseIrradianceOutput(const std::string& name) {
    if (name == "none") return IrradianceOutput::none;
    if (name == "sh") return IrradianceOutput::sh;
    if (name == "cube") return IrradianceOutput::cube;
    if (name == "both") return IrradianceOutput::both;
    throw probe::ProbeError(fmt::format("--irradiance {}: expected none, sh, cube or both", name));
}

IrradianceResult writeIrradiance(probe::StagedOutput& output, const std::string& folder, IrradianceOutput which,
                                 const probe::gpu::Device& device, const probe::CubeImage& source) {
    IrradianceResult result;
    nlohmann::json& entry = result.report;
    entry = nlohmann::json::object();
    probe::CubeImage shCube, cube;
    if (which == IrradianceOutput::sh || which == IrradianceOutput::both) {
        probe::gpu::ShProjector projector(device, source.size);
        const probe::ShCoefficients radiance = projector.project(source);
        result.sh = probe::radianceToIrradiance(radiance);
        result.shDispatches = projector.dispatches();
        shCube = probe::shToCube(result.sh, probe::kIrradianceCubeSize);
        probe::writeExr(output.file(folder + "irradiance_sh.exr"), probe::cubeToStrip(shCube));
        entry["sh"] = {{"convention", probe::kShConvention},      {"radiance", describeSh(radiance)},
                       {"irradiance", describeSh(result.sh)},     {"file", folder + "irradiance_sh.exr"},
                       {"face_size", probe::kIrradianceCubeSize}, {"gpu_ms", medianTimes(projector.timings())}};
    }
    if (which == IrradianceOutput::cube || which == IrradianceOutput::both) {
        const Stopwatch clock;
        cube = probe::irradianceCube(source);
        entry["cube"] = {{"file", folder + "irradiance.exr"},
                         {"face_size", probe::kIrradianceCubeSize},
                         {"source_face_size", std::min(source.size, probe::kIrradianceSourceSize)},
                         {"cpu_seconds", clock.seconds()}};
        probe::writeExr(output.file(folder + "irradiance.exr"), probe::cubeToStrip(cube));
    }
    if (which == IrradianceOutput::both) {
        const probe::IrradianceDifference d = probe::irradianceDifference(shCube, cube);
        entry["sh_against_cube"] = {{"relative_l1", d.relativeL1}, {"max_relative", d.maxRelative}};
    }
    return result;
}

} // namespace probefilter
