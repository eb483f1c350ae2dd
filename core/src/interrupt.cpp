#include "probe/interrupt.h"

#include <csignal>
#include <cstdlib>
#include <thread>

#include <pthread.h>

#include "probe/staged_output.h"

namespace probe {

void removeStagingOnInterrupt() {
    sigset_t signals;
    sigemptyset(&signals);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&signals, s);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::thread([signals] {
        int received = 0;
        if (sigwait(&signals, &received) != 0) return;
        StagedOutput::abandonAll();
        // Die of the signal itself, so that the shell sees why.
        std::signal(received, SIG_DFL);
        sigset_t one;
        sigemptyset(&one);
        sigaddset(&one, received);
        pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
        std::raise(received);
        std::_Exit(128 + received);
    }).detach();
}

} // namespace probe
