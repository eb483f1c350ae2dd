// probe runtime: GGX filtering of reflection probes with Vulkan compute (DESIGN.md).
//
// Two ways to use it:
// - Tools: a Device owns a headless Vulkan 1.2 instance and device, and Filter::run uploads a
//   probe, runs the passes, reads the levels back and times every pass with timestamp queries.
// - Engines: wrap your own VkDevice in a Device and call Filter::record to record the passes into
//   your command buffer, from your cube image to your output cube's mip chain.
//
// All data lives in storage buffers (RGBA32F texels, all levels of all faces packed, see
// shaders/buffers.glsl) and every bilinear read is the shader's own arithmetic, following the
// shared sampling model of probecore, so that the GPU equals the CPU model to float rounding.
// SPIR-V is compiled from shaders/ at build time and embedded; nothing compiles at run time.
// Errors (no device, unsupported format, a table that does not fit) throw probe::ProbeError.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "probe/cube_image.h"
#include "probe/pyramid.h"
#include "probe/roughness.h"
#include "probe/sh.h"
#include "probe/tap_table.h"

namespace probe::gpu {

// A Vulkan physical device as the runtime names it in reports.
struct DeviceInfo {
    int index = -1;     // position in vkEnumeratePhysicalDevices order (what `--device N` picks)
    std::string name;   // deviceName
    std::string driver; // driverName and driverInfo, e.g. "llvmpipe, Mesa 22.3.6 (LLVM 15.0.6)"
    std::string type;   // "discrete", "integrated", "virtual", "cpu" or "other"
    uint32_t apiVersion = 0;
};

// Every Vulkan 1.2+ device with a compute queue, in enumeration order. Throws when there is no
// Vulkan loader or driver at all.
std::vector<DeviceInfo> listDevices();

struct DeviceOptions {
    // "" picks the first discrete GPU, else the first CPU device (lavapipe), else the first device;
    // a number picks that index of listDevices(); anything else is a case-insensitive substring of
    // the device name. No match, or no device at all: ProbeError.
    std::string choice;
    // Enables VK_LAYER_KHRONOS_validation and collects every warning and error it reports
    // (validationMessages()); ProbeError when the layer is not installed.
    bool validation = false;
};

// A Vulkan device and one compute queue: owned (tools) or the caller's (engines).
class Device {
public:
    // Creates an instance and a device. Throws ProbeError naming what is missing.
    explicit Device(const DeviceOptions& options = {});
    // Wraps the caller's device; the caller keeps ownership and must keep it alive. The device must
    // be Vulkan 1.2+; `queue` belongs to `queueFamily`, which must support compute.
    Device(VkInstance instance, VkPhysicalDevice physicalDevice, VkDevice device, uint32_t queueFamily, VkQueue queue);
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const DeviceInfo& info() const;
    // Messages of the validation layer so far (empty without DeviceOptions::validation).
    std::vector<std::string> validationMessages() const;

    VkInstance instance() const;
    VkPhysicalDevice physicalDevice() const;
    VkDevice device() const;
    uint32_t queueFamily() const;
    VkQueue queue() const;

    struct Impl;
    Impl& impl() const { return *impl_; }

private:
    std::unique_ptr<Impl> impl_;
};

enum class Method {
    table,     // pass 1 pyramid + pass 2 tap table (Manson & Sloan); needs subgroup vote in compute shaders
    fis,       // pass 1 pyramid + filtered importance sampling (Krivanek & Colbert)
    reference, // brute force, every source texel for every output texel
};

struct FilterSettings {
    Method method = Method::reference;
    int faceSize = 128; // S_0, a power of two: the source and output level 0
    int levelCount = 7; // M output levels, face size S_0 >> m
    RoughnessMapping mapping = RoughnessMapping::gltf;
    PyramidSettings pyramid;          // pass 1 (table and fis)
    int fisSamples = 32;              // N Hammersley samples per output texel (fis)
    std::vector<int> fisLevelSamples; // per output level, level 0 first (fis); empty: fisSamples at every level
    double fisBias = 0.0;             // added to each sample's level (fis); 0 is the accurate setting
    // The tap table (table method; the caller keeps it alive while the Filter is built). Refused
    // with the reason unless its base size, level count, mapping and pyramid equal the settings'.
    const TapTable* table = nullptr;
    // Only these output levels (ascending, each in [0, M)); empty: every level. Levels left out are
    // neither computed nor read back: run() returns them empty (size 0), record() leaves their mips
    // of the caller's cube alone. A level computed here equals, bit for bit, the same level of a run
    // of every level.
    std::vector<int> levels;
    // Pass 1 builds pyramid levels 1..pyramidDepth only (-1: all, down to 1x1; table and fis), after
    // the border of level 0; none of it when every level computed is a copy (alpha = 0).
    // The levels computed must read no deeper: probe::deepestPyramidLevelRead of their taps
    // (probe/plan.h) is the depth they need.
    int pyramidDepth = -1;
};

// GPU time of one pass: the median over the repeats, from timestamp queries.
struct PassTime {
    std::string name; // "pyramid", "table", "fis", "reference" or "total"
    double medianMs = 0.0;
    std::vector<double> runsMs; // one per repeat
};

// One vkCmdDispatch of a run.
struct Dispatch {
    std::string pass;
    int level = 0;       // the pyramid or output level it writes (pyramid level 0: the source's
                         // border); "sh": the summation stage (0 projects the source)
    uint32_t groups = 0; // workgroups (x; y = z = 1)
};

// The buffers and pipelines of one filter setting, reusable for many probes.
class Filter {
public:
    // Checks the settings (size, levels, device limits) and builds the pipelines and buffers.
    Filter(const Device& device, const FilterSettings& settings);
    ~Filter();
    Filter(const Filter&) = delete;
    Filter& operator=(const Filter&) = delete;

    // Tools: uploads `source` (face size S_0), runs the passes `repeat` times (timed each time) and
    // returns the M output levels (those outside FilterSettings::levels empty).
    CubeLevels run(const CubeImage& source, int repeat = 1);

    // Engines: records the passes into `commandBuffer`: copies mip 0 of `sourceCube` (RGBA32F, 6
    // layers of S_0^2, layout TRANSFER_SRC_OPTIMAL, usage TRANSFER_SRC) into the pyramid and writes
    // mips 0..M-1 of `outputCube` (RGBA32F, 6 layers, layout TRANSFER_DST_OPTIMAL, usage
    // TRANSFER_DST; only the mips of FilterSettings::levels). The caller orders it against its own
    // work. timings() reads the timestamps once the caller's submission has completed.
    void record(VkCommandBuffer commandBuffer, VkImage sourceCube, VkImage outputCube);

    // Per pass and in total, over the runs since the last run() (or the last record()). Empty when
    // the queue has no timestamps.
    std::vector<PassTime> timings() const;
    // Per output level computed, named "level <m>": the time of its pass-2 dispatch (timestamps around
    // it), over the same runs. Levels run with no barrier between them, so on a GPU that overlaps
    // dispatches the split is approximate; their sum is the pass-2 time.
    std::vector<PassTime> levelTimings() const;
    // The dispatches of one run.
    const std::vector<Dispatch>& dispatches() const;
    // The pyramid of the last run (levels 0..pyramidDepth, log2(S_0) by default); empty for the
    // reference method.
    CubeLevels downloadPyramid() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// Order-2 SH projection of a probe on the GPU (shaders/sh_projection.comp): the 9 radiance
// coefficients per channel in the basis, order and signs of probe/sh.h,
// L_lm = sum_t L(t) Y_lm(l_t) dOmega_t over the texels, accumulated in float in a fixed order
// (16 texels per invocation, then trees over workgroups), so every run gives the same bits. The
// diffuse irradiance is probe::radianceToIrradiance of the result.
class ShProjector {
public:
    ShProjector(const Device& device, int faceSize);
    ~ShProjector();
    ShProjector(const ShProjector&) = delete;
    ShProjector& operator=(const ShProjector&) = delete;

    // Uploads `source` (the face size built for) and returns its radiance coefficients.
    ShCoefficients project(const CubeImage& source);
    // GPU time of the last project(): "sh" and "total". Empty when the queue has no timestamps.
    std::vector<PassTime> timings() const;
    // The dispatches of the last project(): pass "sh", level = summation stage.
    const std::vector<Dispatch>& dispatches() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// A material as the sphere renderer shades it.
struct SphereMaterial {
    glm::vec3 baseColor{0.8f};
    float metallic = 0.0f;
    float specular = 1.0f;   // dielectric F0 = 0.04 specular
    float roughness = 0.5f;  // perceptual: the row of the DFG table
    float level = 0.0f;      // the filtered level it reads: probe::roughnessToLevel(mapping, roughness, M)
    bool hasSpecular = true; // false: no specular term (probe::SceneMaterial::hasSpecular)
};

struct SphereScene {
    const CubeLevels* prefiltered = nullptr; // levels 0..M-1 from S_0; the levels no material reads may be empty
    const CubeImage* background = nullptr;   // drawn behind the spheres (bilinear, seamless)
    ShCoefficients irradiance{};             // probe::radianceToIrradiance of the probe's coefficients
    const Image* dfg = nullptr;              // probe::dfgTable (square); unused when no material is specular
    std::vector<SphereMaterial> materials;
    int cellSize = 128; // pixels per sphere, cells left to right
};

// One sphere per material lit by the probe with the split-sum approximation (shaders/spheres.comp:
// prefiltered(R, level) * (F0 A + B) + base (1 - metallic) E(N)), each in its own square cell seen
// from +Z, over the background. Returns linear RGB, cellSize * materials wide, cellSize high.
Image renderSpheres(const Device& device, const SphereScene& scene);

// A tap table compiled into this build: tables/<name>.json as probefit writes it (beside the
// generated <name>.h and <name>.glsl), with its inputs and recorded errors.
struct CompiledTable {
    std::string name;
    TapTable table;
};
// Every compiled-in table, in name order (empty when tables/ holds none).
const std::vector<CompiledTable>& compiledTables();
// The compiled-in table for these settings (the quadratic 8-tap one when there are several), or
// null.
const CompiledTable* findCompiledTable(int faceSize, int levelCount, RoughnessMapping mapping, const PyramidSettings& pyramid);

std::string_view methodName(Method method);
// "table", "fis" or "reference"; ProbeError otherwise.
Method parseMethod(std::string_view name);

} // namespace probe::gpu
