// probe runtime: GGX filtering of reflection probes with Vulkan compute.
//
// Two ways to use it:
// - Tools: a Device owns a headless Vulkan 1.2 instance and device, and Filter::run uploads a
//   probe, runs the passes, reads the levels back and times every pass with timestamp queries.
// - Engines: wrap your own VkDevice in a Device and call Filter::record to record the passes into
//   your command buffer, from your source cube to your output cube's mips (see Filter::record for
//   what the caller owes).
//
// Two ways to read the pyramid (Sampling): through the hardware sampler (the pyramid is a cube
// image with mips, each tap one trilinear textureLod through a seamless sampler: what GPUs are
// built for), or exactly (the pyramid in a storage buffer with a one-texel border per face, every
// bilinear read the shader's own arithmetic, following probecore's sampling model to float
// rounding: the verification mode). SPIR-V is compiled from shaders/ at build time and embedded;
// nothing compiles at run time. Errors (no device, an unsupported format or feature, a table that
// does not fit) throw probe::ProbeError naming what is missing; bad parameter values throw
// probe::ParameterError naming the parameter.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "probe/cube_image.h"
#include "probe/filter_method.h"
#include "probe/roughness.h"
#include "probe/sh.h"
#include "probe/tap_table.h"

namespace probe::gpu {

// A Vulkan physical device as the runtime names it in reports.
struct DeviceInfo {
    int index = -1;     // position in vkEnumeratePhysicalDevices order (what DeviceOptions::choice picks by number)
    std::string name;   // deviceName
    std::string driver; // driverName and driverInfo, e.g. "llvmpipe, Mesa 22.3.6 (LLVM 15.0.6)"
    std::string type;   // "discrete", "integrated", "virtual", "cpu" or "other"
    uint32_t apiVersion = 0;
};

// Every Vulkan 1.2+ device with a compute queue, in enumeration order. Throws when there is no
// Vulkan loader or driver at all.
std::vector<DeviceInfo> listDevices();

struct DeviceOptions {
    // "" picks by type: the first discrete GPU, else integrated, else virtual, else CPU (lavapipe),
    // else the first device; a number picks that index of listDevices(); anything else is a
    // case-insensitive substring of the device name. No match, or no device at all: ParameterError
    // ("device").
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
    // be Vulkan 1.2+, and so must the instance's apiVersion (the runtime's SPIR-V is 1.5); `queue`
    // belongs to `queueFamily`, which must support compute: a compute-only family (an async compute
    // queue) serves, since the runtime records compute and transfer commands alone
    // (tests/gpu_compute_queue_test.cpp). The runtime needs one device feature,
    // timelineSemaphore (Vulkan 1.2 core, which every 1.2 device has: enable it in
    // VkPhysicalDeviceVulkan12Features), and for batches (FilterSettings::batchSize) imageCubeArray
    // (Vulkan 1.0, on every desktop GPU), and no extension (the exact sampling mode's table shader uses
    // subgroup vote, a core operation that every desktop driver has). The Filter's constructor (unless given an
    // initialization command buffer), run() and downloadPyramid(), the SH projector and the sphere
    // renderer submit to `queue` and wait: Vulkan has the caller keep other threads from submitting
    // to it meanwhile.
    Device(VkInstance instance, VkPhysicalDevice physicalDevice, VkDevice device, uint32_t queueFamily, VkQueue queue);
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const DeviceInfo& info() const; // the device's index, name, driver, type and API version
    // Messages of the validation layer so far (empty without DeviceOptions::validation).
    std::vector<std::string> validationMessages() const;

    // The handles the device runs on: its own, or the engine's it was given.
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

// How pass 1 and pass 2 read the pyramid (see the top of this file).
enum class Sampling {
    automatic, // hardware on GPUs; on CPU devices (lavapipe) the mode measured faster there (docs/engine.md)
    hardware,  // a cube image with mips through a seamless trilinear sampler
    exact,     // a bordered storage buffer, the shader's own bilinear arithmetic (probecore's model)
};
std::string_view samplingName(Sampling sampling); // "automatic", "hardware", "exact"
Sampling parseSampling(std::string_view name);    // ParameterError("sampling") otherwise

// The output cube's texel formats: RGBA16F (what engines use), RGBA32F, B10G11R11 (unsigned, 5-bit
// exponents). Values are clamped to the format's largest finite value, so no texel is Inf.
std::string_view formatName(VkFormat format); // "rgba16f", "rgba32f", "b10g11r11", "rgb9e5" (a pyramid's E5B9G9R9)
VkFormat parseFormat(std::string_view name);  // ParameterError("outputFormat") for any other name
// FilterSettings::pyramidFormat by name: "auto" (VK_FORMAT_UNDEFINED), "rgba32f", "rgba16f" or
// "rgb9e5"; ParameterError("pyramidFormat") for any other name.
VkFormat parsePyramidFormat(std::string_view name);

struct FilterSettings {
    FilterMethod method; // table (with its table, which the caller keeps alive), fis, or reference
    int faceSize = 128;  // S_0, a power of two: the source and output level 0
    int levelCount = 7;  // M output levels, face size S_0 >> m
    RoughnessMapping mapping = RoughnessMapping::gltf;
    Sampling sampling = Sampling::automatic;
    // The output cube's format: run()'s own output image, and the format record()'s caller's output
    // cube must have. B10G11R11 goes through a conversion pass where the device cannot store it.
    VkFormat outputFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    // Hardware sampling's pyramid image: R16G16B16A16_SFLOAT, half the memory and the bytes per texel
    // that the sampler reads, R32G32B32A32_SFLOAT, or E5B9G9R9_UFLOAT_PACK32, a quarter of them (a
    // 9-bit mantissa per channel under a shared exponent: each channel within 2^-9 of the texel's
    // brightest; negative values read as 0; written through R32_UINT views, which every device can
    // store); VK_FORMAT_UNDEFINED: RGBA16F where the device can filter and store it (every Vulkan
    // device must), else RGBA32F. An RGBA16F pyramid's largest value is 65504 (E5B9G9R9's 65408): run()
    // scales a brighter probe into that range and its output back; record()'s brighter source texels
    // are clamped there. Exact sampling's pyramid is a float32 buffer: a format is refused there.
    VkFormat pyramidFormat = VK_FORMAT_UNDEFINED;
    // The engine's pipeline cache for the Filter's pipelines (VK_NULL_HANDLE: none); the engine keeps
    // it alive while Filters are built with it and saves its data where it likes.
    VkPipelineCache pipelineCache = VK_NULL_HANDLE;
    // Only these output levels (ascending, each in [0, M)); empty: every level. Levels left out are
    // neither computed nor read back: run() returns them empty (size 0), record() leaves their mips
    // of the caller's cube alone. A level computed here equals, bit for bit, the same level of a run
    // of every level.
    std::vector<int> computedLevels;
    // Recordings that may be in flight at once (K, 1 to 64): the Filter makes up to K sets of what one
    // recording writes and binds (its pyramid, descriptor sets, views and timestamp queries) as
    // recordings need them (one while each completes before the next, as run()'s do) and uses them in
    // turn, so that K probes may be recorded into one submission, or K frames' recordings be pending,
    // before record() refuses another (Filter::record).
    int inFlight = 2;
    // The probes one recording filters (P, 1 to 256, at most a sixth of the device's
    // maxImageArrayLayers), kept as cube-map arrays, as engines keep probes: with P > 1 the source is a
    // VK_IMAGE_VIEW_TYPE_CUBE_ARRAY view of 6 P layers and the output has 6 P layers, probe p in layers
    // 6p to 6p + 5, and every pass covers all P in the dispatches one probe takes, so that their count
    // does not grow with P. Table and FIS only (not the reference, nor FIS on a paraboloid map); needs
    // the device's imageCubeArray feature. Each probe's levels equal, bit for bit, those of a Filter of
    // batchSize 1.
    int batchSize = 1;
    // Pass 1 builds pyramid levels 1..pyramidDepth only (-1: all, down to 1x1; table and fis); none
    // of it when every level computed is a copy (alpha = 0). The levels computed must read no deeper:
    // probe::deepestPyramidLevelRead of their taps (probe/plan.h) is the depth they need.
    int pyramidDepth = -1;
};

// Where Filter::run and Filter::record write timestamp queries. `passes`: at the boundaries of the
// passes (record()'s default); pass 2 then writes consecutive table or FIS levels, up to four, in one
// dispatch. `levels`: a dispatch per output level and a timestamp after each too
// (levelTimings()), which makes a GPU finish a level before it starts the next: each level is then
// timed alone, and pass 2 takes longer than it does with `passes` wherever a GPU would have
// overlapped the small levels (2.8x at 128^2 on an NVIDIA H200, docs/benchmarks.md). `none`: no
// queries are reset or written (an engine's shipping path); timings() is then empty.
enum class Timestamps { passes, levels, none };

// GPU time of one pass: the median over the repeats, from timestamp queries.
struct PassTime {
    std::string name; // "pyramid", "table", "fis", "reference", "convert" or "total"
    double medianMs = 0.0;
    std::vector<double> runsMs; // one per repeat
};

// One vkCmdDispatch of a run.
struct Dispatch {
    std::string pass;
    int level = 0;       // the pyramid or output level it writes (pyramid level 0: the source; the
                         // reference builds it alone, to read it texel by texel; hardware sampling's
                         // last pyramid dispatch writes this mip, 8x8 or smaller, and all below it,
                         // and its others their first mip);
                         // "sh": the summation stage (0 projects the source)
    uint32_t groups = 0; // workgroups in all (the table pass: a layer of them per face)
    int levels = 1;      // pass 2: the output levels it writes, from `level` (up to 12 in one dispatch, 4 on some devices);
                         // pass 1: the mips it writes (the tail's dispatch: from 8x8 down, 4 of them at most)
};

// The caller's source cube for Filter::record, described as the engine made it (record() checks
// every field and refuses a mismatch naming it): a view of type VK_IMAGE_VIEW_TYPE_CUBE (of
// VK_IMAGE_VIEW_TYPE_CUBE_ARRAY with 6 P layers for a batch of P) whose first mip is the S_0 face
// size (other mips are not read), of a format the device can sample
// (VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT): RGBA16F, RGBA32F and B10G11R11 on every desktop GPU.
struct SourceCube {
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageViewType viewType = VK_IMAGE_VIEW_TYPE_MAX_ENUM; // the view's type: VK_IMAGE_VIEW_TYPE_CUBE (or _CUBE_ARRAY)
    uint32_t faceSize = 0;                                  // the view's first mip: S_0
    uint32_t arrayLayers = 6;                               // the view's layers: 6 (6 P)
    // A batch of separately allocated cubes (record() with one SourceCube a probe) copies each source
    // from its image, mip 0 and layers 0-5, which the view shows: usage TRANSFER_SRC.
    VkImage image = VK_NULL_HANDLE;
    VkImageUsageFlags usage = 0; // as created
};

// The caller's output cube for Filter::record, described as the engine made it: a 2D image with 6
// array layers (6 P for a batch of P; cube compatible or not) and at least M mips, mip m of face size
// S_0 >> m, of FilterSettings::outputFormat, with usage STORAGE (TRANSFER_DST where
// outputNeedsTransfer()).
struct OutputCube {
    VkImage image = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t faceSize = 0;       // mip 0's width and height: S_0
    uint32_t mipLevels = 0;      // at least M
    uint32_t arrayLayers = 0;    // 6 (6 P)
    VkImageUsageFlags usage = 0; // as created
};

// How the engine tells a Filter that a recording has completed: the submission of the command buffer
// signals `semaphore`, the Filter's timeline semaphore, to `value` (VkTimelineSemaphoreSubmitInfo).
// Values rise by one per recording, and a value signalled covers every recording before it, so a
// submission that holds several recordings of one Filter signals the last one's value. Recordings
// of one Filter are submitted in the order they were recorded, to the device's queue. A recording
// never submitted is let go by signalling its value from the host (vkSignalSemaphore).
struct Completion {
    VkSemaphore semaphore = VK_NULL_HANDLE;
    uint64_t value = 0;
};

// A part of one probe's (or one batch's) update, for spreading it over frames (Filter::slices, Filter::record): pass 1,
// which builds the Filter's pyramid from the source, and some output levels, which read the pyramid
// that an earlier slice (or this one) built.
struct Slice {
    bool pyramid = false;
    std::vector<int> levels; // ascending, among the levels the Filter computes
    uint32_t dispatches = 0; // what recording it dispatches
    double texelTaps = 0.0;  // its work: output texels times the pyramid reads each takes
};

// The resources and pipelines of one filter setting, reusable for many probes.
class Filter {
public:
    // Checks the settings (method, size, levels, formats, device limits) and builds the pipelines,
    // the pyramid and the tables.
    Filter(const Device& device, const FilterSettings& settings);
    // The same without a submission of its own: the one-time initialization (the tables' uploads, the
    // Filter's images' layouts) is recorded into `initialization`, the engine's command buffer in the
    // recording state for a queue of the device's family (a loading thread may build the Filter). The
    // engine submits it before, or in the same command buffer ahead of, the first record(); the
    // Filter keeps the uploads' staging memory until the first recording has completed, and is not
    // destroyed before the initialization has run.
    Filter(const Device& device, const FilterSettings& settings, VkCommandBuffer initialization);
    ~Filter();
    // The constructor's checks alone, allocating nothing: a tool calls it before it reads a probe,
    // so that settings the device cannot run are refused before the work.
    static void checkLimits(const Device& device, const FilterSettings& settings);
    Filter(const Filter&) = delete;
    Filter& operator=(const Filter&) = delete;

    // Tools: uploads `source` (face size S_0), runs the passes `repeat` times (timed each time, at
    // the places `timestamps` names) and returns the M output levels (those outside
    // FilterSettings::computedLevels empty), read back from the output format.
    CubeLevels run(const CubeImage& source, int repeat = 1, Timestamps timestamps = Timestamps::passes);

    // Engines: records the passes into `commandBuffer`, from `source` to mips 0..M-1 of `output`
    // (only the mips of FilterSettings::computedLevels are written). What the caller owes:
    // - source: usage SAMPLED; the view's subresources in VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
    //   its writes made visible to VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT / VK_ACCESS_SHADER_READ_BIT.
    // - output: usage STORAGE, the mips written in VK_IMAGE_LAYOUT_GENERAL, their earlier use ended by
    //   a barrier to VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT / VK_ACCESS_SHADER_WRITE_BIT.
    //   A B10G11R11 output on a device that cannot store that format is written by a copy instead:
    //   usage TRANSFER_DST and layout VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL (outputNeedsTransfer()).
    // - after: the outputs are written at VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT with
    //   VK_ACCESS_SHADER_WRITE_BIT (VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT when
    //   converted): the caller's barrier makes them visible to its readers.
    // Any finite source gives finite output: the passes read the source clamped to +-2^64
    // (probe::kFilterRangeLimit), and an RGBA16F pyramid holds at most 65504 (E5B9G9R9 65408), so values above those
    // saturate there, where run(), which sees the probe on the host, scales the whole probe by a
    // power of two instead (probe/range_scale.h). An engine whose sources pass 65504 asks for an
    // RGBA32F pyramid.
    // The Filter orders its own work (a barrier before its first dispatch covers its resources' use
    // by a previous recording on the same queue). The command buffer goes to a queue of
    // Device::queueFamily(), whose resources the Filter's are, outside a render pass. record() binds
    // its own compute pipelines, descriptor set and push constants, and resets and writes its
    // timestamp queries: rebind yours after it.
    // In flight: each recording takes a set of the Filter's per-recording resources whose last
    // recording has completed (or makes one, up to FilterSettings::inFlight), writes its descriptor
    // sets and views for this source and output, and returns the Completion that the engine's
    // submission signals.
    // With every set in flight, record() throws ProbeError (nothing is recorded): it never waits, and
    // never reuses what a pending command buffer reads. Destroying the Filter while recordings are in
    // flight is allowed: the Device keeps their resources and releases them once the Completion is
    // signalled (at the Device's next Filter construction or record(), or at its end, which the engine
    // brings about after vkDeviceWaitIdle, as for any Vulkan object). The device must have the
    // timelineSemaphore feature enabled (Vulkan 1.2 core; Device(instance, ...) checks that it exists).
    // Throws ProbeError naming a field of the cubes that does not match, or the format and usage the
    // device lacks.
    [[nodiscard]] Completion record(VkCommandBuffer commandBuffer, const SourceCube& source, const OutputCube& output,
                                    Timestamps timestamps = Timestamps::passes);

    // Engines that keep each probe in a cube of its own: a batch of FilterSettings::batchSize probes,
    // sources[p] to outputs[p], each a cube of 6 layers (SourceCube::image and usage set), in the
    // dispatches of one probe. Each source is copied into the Filter's own cube-map array (of the
    // sources' one format) and each output copied from its own; the copies cost a copy command a
    // cube each way and three barriers. What the caller owes, beside record()'s:
    // - sources: usage TRANSFER_SRC as well; record() moves mip 0 of each to
    //   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL for its copy and back to SHADER_READ_ONLY_OPTIMAL.
    // - outputs: usage TRANSFER_DST (the passes write the Filter's array, the copies the outputs), the
    //   mips written in VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, their earlier use ended by a barrier to
    //   VK_PIPELINE_STAGE_TRANSFER_BIT / VK_ACCESS_TRANSFER_WRITE_BIT; after: written at
    //   VK_PIPELINE_STAGE_TRANSFER_BIT with VK_ACCESS_TRANSFER_WRITE_BIT.
    // Whole updates only (no slices). Throws ProbeError naming the field of the cube that does not match.
    [[nodiscard]] Completion record(VkCommandBuffer commandBuffer, const std::vector<SourceCube>& sources,
                                    const std::vector<OutputCube>& outputs, Timestamps timestamps = Timestamps::passes);

    // Time slicing: the update cut into at most `count` slices (pass 1 alone first, then the levels
    // in order, grouped so that their texel-taps come out about even; one slice: the whole update,
    // as record() records it), each slice's cost known
    // before anything is recorded. A level's texel-taps are its texels times the reads each takes: a
    // table's taps in use times the 2 + 7/16 frames a texel blends on average, FIS's samples, one for
    // a copy, every source texel for the reference; pass 1's are the source's texels (level 0, one read
    // each) and four reads for each texel of the levels below (and of a paraboloid map).
    std::vector<Slice> slices(int count) const;
    // Records one slice, as record() records them all; with timestamps (Timestamps::passes or
    // levels), timings() then gives its GPU time as "slice" and "total". The engine records the
    // slices in order, one frame each (or several in a frame), and keeps the source holding the same
    // probe until the last has run: the pyramid slice and the copy of level 0 read it. Recording a
    // slice into a second output cube of the same shape leaves the first, with the old levels,
    // readable until the last slice completes; the engine then swaps them. A pyramid slice takes a set
    // as record() does; a slice of levels reads the pyramid in its update's set, whose earlier slices
    // may still be pending, and is refused when it comes before any pyramid slice, when that set has
    // since been taken by another recording, or when its source or output differs from the pyramid
    // slice's. The same checks as record(), and the slice's levels must be the Filter's.
    [[nodiscard]] Completion record(VkCommandBuffer commandBuffer, const SourceCube& source, const OutputCube& output, const Slice& slice,
                                    Timestamps timestamps = Timestamps::none);
    // Tools: uploads `source`, runs `slices` in order, one submission each and timed, and returns the
    // output levels as run() does; sliceMs gets each slice's GPU time (empty without timestamps).
    CubeLevels run(const CubeImage& source, const std::vector<Slice>& slices, std::vector<double>& sliceMs);

    // Tools: a batch of FilterSettings::batchSize probes, uploaded into one cube-map array and filtered
    // by one recording, submitted `repeat` times; returns each probe's levels as run() does (the
    // one-probe run() needs a batch size of 1). timings() then gives the batch's GPU time as "batch"
    // and "total".
    std::vector<CubeLevels> run(const std::vector<CubeImage>& sources, int repeat = 1);

    // The output cube a recording writes, sized by the Filter, as the engine creates it (vkCreateImage):
    // cube compatible, face size S_0, M mips, 6 layers (6 P for a batch), the output format, optimal
    // tiling, usage STORAGE (TRANSFER_DST where outputNeedsTransfer()) and SAMPLED for the engine's
    // readers (add the engine's own usages). An engine spreading updates over frames (slices) creates
    // two from it and swaps them.
    VkImageCreateInfo outputImageInfo() const;
    // The pyramid's sampling mode (automatic resolved), the pyramid's format (RGBA16F or RGBA32F),
    // and whether a B10G11R11 output is converted through a copy.
    Sampling sampling() const;
    VkFormat pyramidFormat() const;
    bool outputNeedsTransfer() const;

    // Per pass and in total, over the runs since the last run() (or the last record(), once the
    // submission of its command buffer has completed: the queries are waited for). Empty when the
    // queue has no timestamps.
    std::vector<PassTime> timings() const;
    // Per output level computed, named "level <m>": the time of its pass-2 dispatch alone, over the
    // runs of the last run(), when that asked for Timestamps::levels; their sum is that run's pass-2
    // time. Empty after any other run() or a record().
    std::vector<PassTime> levelTimings() const;
    // The dispatches of one run, and the pipeline barriers between them (the first one orders the run
    // after a previous use of the Filter's resources).
    const std::vector<Dispatch>& dispatches() const;
    int barriers() const;
    // The pyramid of the last run (levels 0..pyramidDepth, log2(S_0) by default; a batch's first
    // probe's); empty for the reference method.
    CubeLevels downloadPyramid() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// One call for the common case, as Filament's prefilter is: builds a Filter of `settings`, filters
// `source` (face size settings.faceSize) once and returns the M output levels (those outside
// FilterSettings::computedLevels empty). An engine that filters often keeps a Filter and records it.
CubeLevels filterProbe(const Device& device, const FilterSettings& settings, const CubeImage& source);

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

// BC6H (VK_FORMAT_BC6H_UFLOAT_BLOCK) on the GPU (shaders/bc6h_encode.comp), for a filtered cube's
// levels: per level the six faces in order, each face's 4x4 blocks row by row, 16 bytes a block (a
// level smaller than 4x4 fills one block), as Vulkan and KTX2 lay them out. Each block takes the best
// of the one-region modes and, where none comes within one unit in the last place of a half on
// average, of the two-region modes on all 32 shapes, by the decoder's own arithmetic (docs/
// output-formats.md). Unsigned: negative values encode as 0, values above 65504 as 65504.
class Bc6hEncoder {
public:
    Bc6hEncoder(const Device& device, int faceSize, int levelCount);
    ~Bc6hEncoder();
    Bc6hEncoder(const Bc6hEncoder&) = delete;
    Bc6hEncoder& operator=(const Bc6hEncoder&) = delete;

    // Each level's blocks (probe::bc6hLevelBytes, probe/bc6h.h); a level left empty (not computed) encodes
    // as black.
    std::vector<std::vector<uint8_t>> encode(const CubeLevels& levels);
    // Engines: records the encoding of `source`, the output cube a Filter wrote (every level), into
    // `target`, in the same command buffer after Filter::record (or in a later one on the same queue).
    // What the caller owes:
    // - source: RGBA32F or RGBA16F, usage TRANSFER_SRC, mips 0..M-1 in VK_IMAGE_LAYOUT_GENERAL, as
    //   Filter::record leaves them (its writes need no barrier of the caller's: record() makes them
    //   visible to its copy, for which it moves them to TRANSFER_SRC_OPTIMAL and back to GENERAL).
    // - target: a VK_FORMAT_BC6H_UFLOAT_BLOCK cube of the encoder's face size, at least M mips and 6
    //   layers, usage TRANSFER_DST, its mips 0..M-1 in VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL.
    // - after: the blocks are written at VK_PIPELINE_STAGE_TRANSFER_BIT / VK_ACCESS_TRANSFER_WRITE_BIT:
    //   the caller's barrier (and layout transition) makes them visible to its readers.
    // The encoder orders its own work (a barrier before its copy covers its buffers' use by an earlier
    // recording on the same queue), binds its own pipeline and descriptor set, and writes no timestamps.
    // The blocks equal encode()'s of the same levels. Throws ProbeError naming a field of the source
    // that does not match.
    void record(VkCommandBuffer commandBuffer, const OutputCube& source, VkImage target);
    // GPU time of the last encode(): "bc6h" and "total". Empty when the queue has no timestamps.
    std::vector<PassTime> timings() const;

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
    // KHR_materials_sheen: black is none; the Charlie level it reads, as `level`.
    glm::vec3 sheenColor{0.0f};
    float sheenRoughness = 0.0f;
    float sheenLevel = 0.0f;

    bool hasSheen() const { return sheenColor.r > 0.0f || sheenColor.g > 0.0f || sheenColor.b > 0.0f; }
};

struct SphereScene {
    const CubeLevels* prefiltered = nullptr; // levels 0..M-1 from S_0; the levels no material reads may be empty
    const CubeImage* background = nullptr;   // drawn behind the spheres (bilinear, seamless)
    ShCoefficients irradiance{};             // probe::radianceToIrradiance of the probe's coefficients
    const Image* dfg = nullptr;              // probe::dfgTable (square); unused when no material is specular
    const CubeLevels* sheen = nullptr;       // the Charlie levels, as `prefiltered`; unused when no material has sheen
    const Image* sheenTable = nullptr;       // probe::sheenTable (square); the same
    std::vector<SphereMaterial> materials;
    int cellSize = 128; // pixels per sphere, cells left to right
};

// One sphere per material lit by the probe with the split-sum approximation (shaders/spheres.comp:
// prefiltered(R, level) * (F0 A + B) + base (1 - metallic) E(N)), under a sheen layer where the
// material has one (KHR_materials_sheen: sheenColor charlie(R, sheenLevel) S + (1 - max(sheenColor) E)
// times the rest, S and E from the sheen table), each in its own square cell seen from +Z, over the
// background. Returns linear RGB, cellSize * materials wide, cellSize high.
Image renderSpheres(const Device& device, const SphereScene& scene);

// A tap table compiled into this build from its generated header (tables/<name>.h, as probefit
// writes it): the tables that the command line picks by default (the build option
// PROBE_COMPILED_TABLES lists them). Others are read from their files (probe::readTable).
struct CompiledTable {
    std::string name;
    TapTable table;
};
// Every compiled-in table, in name order.
const std::vector<CompiledTable>& compiledTables();
// The compiled-in table for these settings and lobe (the quadratic 8-tap one when there are
// several), or null.
const CompiledTable* findCompiledTable(int faceSize, int levelCount, const RoughnessMapping& mapping, const PyramidSettings& pyramid,
                                       Lobe lobe = Lobe::ggx);

} // namespace probe::gpu
