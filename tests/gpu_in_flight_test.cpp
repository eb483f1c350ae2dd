// Recordings in flight (FilterSettings::inFlight, Completion): several probes recorded with one
// Filter into one submission each get their own levels; a recording beyond the sets in flight is
// refused, not recorded; a Filter destroyed before its recordings complete leaves their resources to
// the Device, which releases them once the Completion is signalled; slices keep their update's set.
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

// The tools' batch: every probe in its own set, one submission, each probe's levels those of its own
// run(), its dispatches and barriers the sum of the probes', timed as a whole; more probes than sets
// are refused.
TEST_F(GpuTest, BatchRunEqualsRunsOneByOne) {
    const gpu::Device& device = testDevice();
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) {
        const gpu::FilterSettings settings = fisSettings(sampling, 3);
        gpu::Filter filter(device, settings);
        const std::vector<CubeImage> sources{randomProbe(16, 80), randomProbe(16, 81), randomProbe(16, 82)};
        const std::vector<CubeLevels> batch = filter.run(sources);
        const std::size_t batchDispatches = filter.dispatches().size();
        const int batchBarriers = filter.barriers();
        ASSERT_EQ(batch.size(), sources.size());
        const std::vector<gpu::PassTime> timings = filter.timings();
        ASSERT_FALSE(timings.empty());
        EXPECT_EQ(timings.front().name, "batch");
        for (std::size_t p = 0; p < sources.size(); ++p) {
            const CubeLevels alone = filter.run(sources[p]);
            for (int m = 0; m < settings.levelCount; ++m)
                EXPECT_EQ(batch[p][m].rgb, alone[m].rgb) << gpu::samplingName(sampling) << ", probe " << p << ", level " << m;
        }
        EXPECT_EQ(batchDispatches, sources.size() * filter.dispatches().size());
        EXPECT_EQ(batchBarriers, int(sources.size()) * filter.barriers());
        EXPECT_THROW(filter.run(std::vector<CubeImage>(4, sources[0])), ParameterError);
        EXPECT_THROW(filter.run(std::vector<CubeImage>{}), ParameterError);
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
