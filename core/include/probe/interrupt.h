// SIGINT, SIGTERM and SIGHUP end a run without leaving its staging folder or file behind.
#pragma once

namespace probe {

// Blocks the three signals in the calling thread (so in every thread it starts later: call it first
// in main) and starts a thread that waits for them, removes every staging folder and file
// (probe::StagedOutput::abandonAll) and ends the process by the same signal.
void removeStagingOnInterrupt();

} // namespace probe
