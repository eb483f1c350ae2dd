// Recordings in flight (FilterSettings::inFlight, Completion): several probes recorded with one
// Filter into one submission each get their own levels; a recording beyond the sets in flight is
// refused, not recorded; a Filter destroyed before its recordings complete leaves their resources to
// the Device, which releases them once the Completion is signalled; slices keep their update's set.
// Batches (FilterSettings::batchSize): many probes in one recording, in the dispatches of one.
// Every case runs under the validation layer with synchronization validation on (gpu_test_support.h),
// which is live: it reports two unordered writes.
#include <algorithm>
#include <cstdlib>

#include <fmt/format.h>

#include "buffer.h"
#include "device.h"
#include "engine_caller.h"
#include "gpu_test_support.h"
#include "probe/error.h"
#include "probe/table_io.h"
#include "submission.h"

using namespace probe;
using namespace probetest;

namespace {

gpu::FilterSettings fisSettings(gpu::Sampling sampling, int inFlight) {
    gpu::FilterSettings s;
    s.method.kind = MethodKind::fis;
    s.faceSize = 16;
    s.levelCount = 4;
    s.sampling = sampling;
    s.inFlight = inFlight;
    return s;
}

} // namespace

// As many probes as recordings in flight, recorded with one Filter into one command buffer and one
// submission (which signals the last Completion): each output holds its own probe's levels, bit for
// bit those of run(), in both sampling modes.
TEST_F(GpuTest, ProbesRecordedIntoOneSubmissionKeepTheirOwnLevels) {
    const gpu::Device& device = testDevice();
    const Caller c = callerOf(device);
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware})
        for (int inFlight : {2, 3}) {
            const gpu::FilterSettings settings = fisSettings(sampling, inFlight);
            gpu::Filter filter(device, settings);
            std::vector<CubeImage> sources;
            std::vector<std::unique_ptr<EngineProbe>> probes;
            for (int p = 0; p < inFlight; ++p) {
                sources.push_back(randomProbe(settings.faceSize, 40 + p));
                probes.push_back(std::make_unique<EngineProbe>(c, sources.back(), settings.levelCount));
            }
            EngineCommands commands(c);
            for (const auto& probe : probes) probe->upload(commands.cmd);
            gpu::Completion last;
            for (const auto& probe : probes) last = filter.record(commands.cmd, probe->source(), probe->output());
            EXPECT_EQ(last.value, uint64_t(inFlight));
            for (const auto& probe : probes) probe->readBack(commands.cmd);
            commands.submit(last);
            for (int p = 0; p < inFlight; ++p) {
                const CubeLevels expected = filter.run(sources[p]);
                const CubeLevels recorded = probes[p]->levels();
                for (int m = 0; m < settings.levelCount; ++m)
                    EXPECT_EQ(recorded[m].rgb, expected[m].rgb)
                        << gpu::samplingName(sampling) << ", " << inFlight << " in flight, probe " << p << ", level " << m;
            }
        }
}

// With every set in flight, record() refuses (and records nothing) until a Completion is signalled:
// by the submission, or from the host for recordings never submitted. The refusal names the setting.
TEST_F(GpuTest, RecordingBeyondInFlightIsRefused) {
    const gpu::Device& device = testDevice();
    const Caller c = callerOf(device);
    const gpu::FilterSettings settings = fisSettings(gpu::Sampling::exact, 2);
    gpu::Filter filter(device, settings);
    const CubeImage source = randomProbe(settings.faceSize, 50);
    EngineProbe probe(c, source, settings.levelCount);
    EngineCommands commands(c);
    probe.upload(commands.cmd);
    const gpu::Completion first = filter.record(commands.cmd, probe.source(), probe.output());
    const gpu::Completion second = filter.record(commands.cmd, probe.source(), probe.output());
    EXPECT_EQ(first.semaphore, second.semaphore);
    EXPECT_EQ(second.value, first.value + 1);
    try {
        (void)filter.record(commands.cmd, probe.source(), probe.output());
        ADD_FAILURE() << "a third recording with two in flight: not refused";
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("inFlight"), std::string::npos) << e.what();
    }
    probe.readBack(commands.cmd);
    commands.submit(second); // covers the first too
    const gpu::Completion third = filter.record(commands.cmd, probe.source(), probe.output());
    EXPECT_EQ(third.value, second.value + 1);
    probe.readBack(commands.cmd);
    commands.submit(third);
    const CubeLevels expected = filter.run(source);
    for (int m = 0; m < settings.levelCount; ++m) EXPECT_EQ(probe.levels()[m].rgb, expected[m].rgb) << "level " << m;

    // Recordings never submitted: the engine lets them go by signalling from the host.
    const gpu::Completion unsubmitted[2] = {filter.record(commands.cmd, probe.source(), probe.output()),
                                            filter.record(commands.cmd, probe.source(), probe.output())};
    EXPECT_THROW((void)filter.record(commands.cmd, probe.source(), probe.output()), ProbeError);
    vkEndCommandBuffer(commands.cmd);
    vkResetCommandBuffer(commands.cmd, 0);
    commands.begin();
    const VkSemaphoreSignalInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SIGNAL_INFO, nullptr, unsubmitted[1].semaphore, unsubmitted[1].value};
    ASSERT_EQ(vkSignalSemaphore(c.device, &signal), VK_SUCCESS);
    EXPECT_EQ(filter.record(commands.cmd, probe.source(), probe.output()).value, unsubmitted[1].value + 1);
    vkEndCommandBuffer(commands.cmd);

    for (int inFlight : {0, -1, 65}) EXPECT_THROW(gpu::Filter(device, fisSettings(gpu::Sampling::exact, inFlight)), ParameterError);
}

// A Filter destroyed after record() and before the submission: the submission runs (its levels are
// right, the validation layer sees nothing destroyed in use), and the Device releases what the
// recording read once its Completion is signalled, at the next Filter it builds.
TEST_F(GpuTest, FilterDestroyedBeforeItsRecordingCompletes) {
    const gpu::Device& owner = testDevice();
    const Caller c = callerOf(owner);
    const gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) {
        const gpu::FilterSettings settings = fisSettings(sampling, 2);
        const CubeImage source = randomProbe(settings.faceSize, 60);
        const CubeLevels expected = gpu::Filter(owner, settings).run(source);
        EngineProbe probe(c, source, settings.levelCount);
        EngineCommands commands(c);
        probe.upload(commands.cmd);
        auto filter = std::make_unique<gpu::Filter>(wrapped, settings);
        const gpu::Completion done = filter->record(commands.cmd, probe.source(), probe.output());
        probe.readBack(commands.cmd);
        filter.reset();
        EXPECT_EQ(wrapped.impl().retired.size(), 1u) << "the recording's resources, kept";
        commands.submit(done);
        for (int m = 0; m < settings.levelCount; ++m) EXPECT_EQ(probe.levels()[m].rgb, expected[m].rgb) << "level " << m;
        const gpu::Filter next(wrapped, settings);
        EXPECT_TRUE(wrapped.impl().retired.empty()) << "released once complete";
    }
    // A Filter whose recordings have all completed is released at once.
    gpu::Filter(wrapped, fisSettings(gpu::Sampling::exact, 2)).run(randomProbe(16, 61));
    EXPECT_TRUE(wrapped.impl().retired.empty());
}

// Slices keep their update's set: the level slices read the pyramid their pyramid slice built, even
// with that slice still pending and another recording in between; a level slice before any pyramid
// slice, or into another output than its update's, is refused.
TEST_F(GpuTest, SlicesKeepTheirUpdatesSet) {
    const gpu::Device& device = testDevice();
    const Caller c = callerOf(device);
    const gpu::FilterSettings settings = fisSettings(gpu::Sampling::exact, 2);
    gpu::Filter filter(device, settings);
    const CubeImage source = randomProbe(settings.faceSize, 70), other = randomProbe(settings.faceSize, 71);
    const CubeLevels expected = filter.run(source), expectedOther = filter.run(other);
    EngineProbe probe(c, source, settings.levelCount), otherProbe(c, other, settings.levelCount);
    const std::vector<gpu::Slice> slices = filter.slices(3);
    ASSERT_EQ(slices.size(), 3u);
    EngineCommands commands(c);
    EXPECT_THROW((void)filter.record(commands.cmd, probe.source(), probe.output(), slices[1]), ProbeError);
    probe.upload(commands.cmd);
    otherProbe.upload(commands.cmd);
    (void)filter.record(commands.cmd, probe.source(), probe.output(), slices[0]);
    // Another probe's whole update takes the other set; the level slices still find theirs.
    (void)filter.record(commands.cmd, otherProbe.source(), otherProbe.output());
    (void)filter.record(commands.cmd, probe.source(), probe.output(), slices[1]);
    EXPECT_THROW((void)filter.record(commands.cmd, otherProbe.source(), otherProbe.output(), slices[2]), ProbeError);
    const gpu::Completion done = filter.record(commands.cmd, probe.source(), probe.output(), slices[2]);
    probe.readBack(commands.cmd);
    otherProbe.readBack(commands.cmd);
    commands.submit(done);
    for (int m = 0; m < settings.levelCount; ++m) {
        EXPECT_EQ(probe.levels()[m].rgb, expected[m].rgb) << "sliced, level " << m;
        EXPECT_EQ(otherProbe.levels()[m].rgb, expectedOther[m].rgb) << "whole, level " << m;
    }
}

// A batch (FilterSettings::batchSize): the probes as the cubes of cube-map arrays, one recording.
// Each probe's levels equal, bit for bit, those of a Filter of one probe, for the table (16^2, with
// its copied level 0) and FIS (32^2 and 64^2, where hardware sampling's first pyramid dispatch writes
// mips 0 and 1, and mips 0 to 2; 256^2 with hardware sampling alone, where mips 3 and 4 share one),
// in both sampling modes and with a converted B10G11R11 output; the batch takes the
// dispatches and barriers one probe takes, whatever its size. A run of another number of probes, and
// a batch of the reference or of FIS on a paraboloid map, are refused.
TEST_F(GpuTest, BatchEqualsProbesOneByOneInTheDispatchesOfOne) {
    const gpu::Device& device = testDevice();
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    for (const int size : {16, 32, 64, 256})
        for (const gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware})
            for (const VkFormat format : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32}) {
                if (size == 256 && sampling == gpu::Sampling::exact) continue;
                const MethodKind kind = size == 16 ? MethodKind::table : MethodKind::fis;
                gpu::FilterSettings settings = fisSettings(sampling, 2);
                settings.method.kind = kind;
                settings.method.table = &table;
                settings.faceSize = size;
                const std::vector<CubeImage> sources{randomProbe(settings.faceSize, 80), randomProbe(settings.faceSize, 81),
                                                     randomProbe(settings.faceSize, 82)};
                settings.outputFormat = format;
                const std::string name =
                    fmt::format("{} {}^2, {}, {}", methodKindName(kind), size, gpu::samplingName(sampling), gpu::formatName(format));
                gpu::Filter alone(device, settings);
                settings.batchSize = int(sources.size());
                gpu::Filter batch(device, settings);
                const std::vector<CubeLevels> levels = batch.run(sources);
                ASSERT_EQ(levels.size(), sources.size()) << name;
                for (std::size_t p = 0; p < sources.size(); ++p) {
                    const CubeLevels expected = alone.run(sources[p]);
                    for (int m = 0; m < settings.levelCount; ++m)
                        EXPECT_EQ(levels[p][m].rgb, expected[m].rgb) << name << ", probe " << p << ", level " << m;
                }
                EXPECT_EQ(batch.dispatches().size(), alone.dispatches().size()) << name;
                EXPECT_EQ(batch.barriers(), alone.barriers()) << name;
                EXPECT_FALSE(batch.timings().empty()) << name;
                EXPECT_THROW(batch.run(sources.front()), ParameterError) << name;
                EXPECT_THROW(batch.run(std::vector<CubeImage>(4, sources[0])), ParameterError) << name;
            }
    gpu::FilterSettings reference = fisSettings(gpu::Sampling::exact, 2);
    reference.method.kind = MethodKind::reference;
    reference.batchSize = 2;
    EXPECT_THROW(gpu::Filter(device, reference), ParameterError);
    gpu::FilterSettings paraboloid = fisSettings(gpu::Sampling::exact, 2);
    paraboloid.method.fis.map = FisMap::paraboloid;
    paraboloid.batchSize = 2;
    EXPECT_THROW(gpu::Filter(device, paraboloid), ParameterError);
    for (int size : {0, 257}) {
        gpu::FilterSettings s = fisSettings(gpu::Sampling::exact, 2);
        s.batchSize = size;
        EXPECT_THROW(gpu::Filter(device, s), ParameterError) << size;
    }
}

// A batch whose pyramid levels exceed the device's storage-buffer range is written in windows of whole
// faces across its cubes (FilterPlan::pyramidWindows), and each probe's levels stay its own.
TEST_F(GpuTest, BatchPyramidWrittenInWindowsEqualsProbesOneByOne) {
    const gpu::Device& shared = testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    // Level 0 of three 16^2 cubes (18 faces of 18^2 texels) in windows of four faces.
    device.impl().limits.maxStorageBufferRange = 4 * 18 * 18 * 16;
    device.impl().imageCubeArray = shared.impl().imageCubeArray;
    gpu::FilterSettings settings = fisSettings(gpu::Sampling::exact, 2);
    const std::vector<CubeImage> sources{randomProbe(16, 90), randomProbe(16, 91), randomProbe(16, 92)};
    gpu::Filter alone(shared, settings);
    settings.batchSize = int(sources.size());
    gpu::Filter batch(device, settings);
    const std::vector<CubeLevels> levels = batch.run(sources);
    const auto level0 = std::count_if(batch.dispatches().begin(), batch.dispatches().end(),
                                      [](const gpu::Dispatch& d) { return d.pass == "pyramid" && d.level == 0; });
    EXPECT_EQ(level0, 5) << "18 faces in windows of 4, each writing its corners";
    for (std::size_t p = 0; p < sources.size(); ++p) {
        const CubeLevels expected = alone.run(sources[p]);
        for (int m = 0; m < settings.levelCount; ++m) EXPECT_EQ(levels[p][m].rgb, expected[m].rgb) << "probe " << p << ", level " << m;
    }
}

// The validation layer runs with synchronization validation (every GPU test's device): two writes of
// one buffer with no barrier between them are reported as a hazard. A device of its own, so that
// the report fails no other test.
TEST(SynchronizationValidation, ReportsTwoUnorderedWrites) {
    gpu::DeviceOptions options;
    options.validation = true;
    if (const char* choice = std::getenv("PROBE_TEST_DEVICE")) options.choice = choice;
    const gpu::Device device(options);
    const gpu::Buffer buffer(device, 1024, gpu::Buffer::Kind::storage);
    gpu::Submission submission(device);
    VkCommandBuffer cmd = submission.begin();
    vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 1u);
    vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 2u);
    submission.submitAndWait(cmd);
    submission.release(cmd);
    const std::vector<std::string> messages = device.validationMessages();
    EXPECT_TRUE(
        std::any_of(messages.begin(), messages.end(), [](const std::string& m) { return m.find("SYNC-HAZARD") != std::string::npos; }))
        << messages.size() << " message(s)";
}
