// Static GPU cost of the runtime's compute pipelines: each pipeline compiled by the Vulkan driver, which
// reports its statistics through VK_KHR_pipeline_executable_properties (RADV with its ACO compiler:
// instructions, registers, spills, and ACO's latency and throughput estimates). A proxy for the cost on
// that GPU, not a time: nothing is dispatched, and RADV's null device (bench/scripts/shader-stats) compiles for
// an AMD GPU that the machine need not have.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace probe::stats {

// One pipeline as the runtime creates it: shaders/CMakeLists.txt's SPIR-V and the specialization
// constants (specialization[i] sets constant_id i; empty: the shader's defaults).
struct ShaderVariant {
    std::string name; // the SPIR-V's name, then the specialization's, e.g. "table_filter_hardware_rgba32f quad"
    std::span<const uint32_t> spirv;
    std::vector<int32_t> specialization;
};

// Every compute pipeline the runtime creates: each SPIR-V it embeds, the table filter with quadratic
// and with constant tables, the pyramid passes with the B-spline and the box kernel; and the engine
// drop-in shaders with the default table (bench/shader_stats/engine_pyramid.comp, bench/shader_stats/engine_table_filter.comp).
std::vector<ShaderVariant> runtimeVariants();

// The driver's statistics of one compiled pipeline (-1 where the driver does not report one).
struct PipelineStatistics {
    int64_t instructions = -1;
    int64_t vgprs = -1;
    int64_t sgprs = -1;
    int64_t spilledVgprs = -1;
    int64_t spilledSgprs = -1;
    int64_t latency = -1;           // ACO's estimate of one invocation's cycles, stalls included
    int64_t inverseThroughput = -1; // ACO's estimate of the cycles per invocation with the SIMD full
    // Vector memory instructions in the disassembly (AMD: buffer_, image_, global_ ...): the reads
    // that go through the texture units, one address per invocation; scalar loads (s_load,
    // s_buffer_load) read one value for the whole wave.
    int64_t vectorMemory = -1;
};

// A loop to measure, the table filter's taps or FIS's samples: the pipeline as the runtime creates it,
// whose loop counts are push constants or table data, and two compilations whose counts are constants
// (table_filter.comp's kFixedTapGroups, fis.comp's kFixedSampleCount), which the driver
// unrolls.
struct LoopVariant {
    std::string name; // e.g. "table_filter_hardware_rgba32f quad"
    std::string unit; // "tap" or "sample"
    std::span<const uint32_t> spirv;
    std::vector<int32_t> runtime, fixedA, fixedB; // the three specializations
    int unitsA = 0, unitsB = 0;                   // taps or samples in the code of fixedA and fixedB
    int unitsPerIteration = 0;                    // taps or samples in the code of one pass of the runtime's loops
};

// The table filter (quad and constant tables) and FIS, hardware and exact sampling, and FIS on the
// dual-paraboloid map; RGBA32F output.
std::vector<LoopVariant> loopVariants();

// The cost of one tap or sample, from the instruction counts of a LoopVariant's three compilations.
struct LoopCost {
    LoopVariant loop;
    PipelineStatistics runtime, a, b;

    // The unrolled loop body: the difference between the two fixed counts.
    double instructionsPerUnit() const { return double(b.instructions - a.instructions) / (loop.unitsB - loop.unitsA); }
    // The instructions outside the loop bodies.
    double fixedInstructions() const { return double(a.instructions) - loop.unitsA * instructionsPerUnit(); }
    // The runtime's loop, its counting and branching included: its instructions beyond the fixed ones,
    // per tap or sample in one pass.
    double runtimeInstructionsPerUnit() const { return (double(runtime.instructions) - fixedInstructions()) / loop.unitsPerIteration; }
    // The vector memory instructions per tap or sample, from the two fixed counts.
    double vectorMemoryPerUnit() const { return double(b.vectorMemory - a.vectorMemory) / (loop.unitsB - loop.unitsA); }
    // The runtime pipeline's instructions for an output texel whose loop runs `units` taps or samples:
    // the code outside the loop once, the runtime loop per tap or sample.
    double instructionsPerTexel(double units) const { return fixedInstructions() + units * runtimeInstructionsPerUnit(); }
};

// Taps per output texel of a table with N taps per frame, on average over a face: two frames
// everywhere and a third in the edge ring (table_filter.comp).
double tableFramesPerTexel();

// A Vulkan device that reports pipeline statistics: the first one with
// VK_KHR_pipeline_executable_properties. Throws probe::ProbeError when there is none.
class StatisticsDevice {
public:
    StatisticsDevice();
    ~StatisticsDevice();
    StatisticsDevice(const StatisticsDevice&) = delete;
    StatisticsDevice& operator=(const StatisticsDevice&) = delete;

    std::string name() const;   // e.g. "Null hardware (RADV NAVI21)"
    std::string driver() const; // e.g. "radv Mesa 22.3.6"
    // Compiles one pipeline with the runtime's ComputePipeline and reads its statistics.
    PipelineStatistics compile(std::span<const uint32_t> spirv, std::span<const int32_t> specialization) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// Compiles the loop's three pipelines.
LoopCost measureLoop(const StatisticsDevice& device, const LoopVariant& loop);

} // namespace probe::stats
