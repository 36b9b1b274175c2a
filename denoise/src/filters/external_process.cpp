// Runs a program for the external filter (external_process.h) with posix_spawn: no shell, its
// own process group so that a timeout or a cancel kills whatever it started too.
#include "filters/external_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "glint/image/error.h"

extern char** environ;

namespace glint::denoise::detail {

namespace {

constexpr std::size_t kTailBytes = 4096;

// Closes a descriptor once.
struct Fd {
    int fd = -1;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

// A started child: killed with its group and reaped unless it was reaped already.
struct Child {
    pid_t pid = -1;
    bool reaped = false;
    int status = 0;
    ~Child() {
        if (pid > 0 && !reaped) {
            ::kill(-pid, SIGKILL);
            while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
            }
        }
    }
    // True once the child has ended (without reaping it, so its group id stays reserved).
    bool ended() const {
        siginfo_t info{};
        info.si_pid = 0;
        return ::waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
               info.si_pid == pid;
    }
    // Kills whatever is left of the group, then reaps the child.
    void finish() {
        ::kill(-pid, SIGKILL);
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        reaped = true;
    }
};

// Appends what the pipe holds now to `tail` (keeping its last kTailBytes); false at end of file.
bool drain(int fd, std::string& tail) {
    char buffer[4096];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n > 0) {
            tail.append(buffer, std::size_t(n));
            if (tail.size() > 2 * kTailBytes) tail.erase(0, tail.size() - kTailBytes);
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK);
    }
}

}  // namespace

std::string lastLines(const std::string& text, int count) {
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (!line.empty()) lines.push_back(std::move(line));
        start = end + 1;
    }
    std::string out;
    const std::size_t first = lines.size() > std::size_t(count) ? lines.size() - count : 0;
    for (std::size_t i = first; i < lines.size(); ++i) out += (out.empty() ? "" : " | ") + lines[i];
    return out;
}

ProcessOutcome runProcess(const std::vector<std::string>& argv,
                          const std::filesystem::path& workDir, double timeoutSeconds,
                          const std::function<bool()>& keepGoing) {
    GLINT_CHECK(!argv.empty());
    // The stderr pipe: close-on-exec, so that programs other threads start do not inherit it.
    int ends[2];
    if (::pipe2(ends, O_CLOEXEC | O_NONBLOCK) != 0)
        throw Error(ErrorKind::Io, std::string("cannot create a pipe: ") + std::strerror(errno));
    Fd readEnd{ends[0]}, writeEnd{ends[1]};

    // stdin from /dev/null, stdout discarded, stderr into the pipe; run in the work folder.
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, writeEnd.fd, 2);
    posix_spawn_file_actions_addchdir_np(&actions, workDir.c_str());
    // Its own process group, default signal handling and an empty signal mask.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setflags(
        &attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    Child child;
    const int rc =
        ::posix_spawn(&child.pid, argv[0].c_str(), &actions, &attr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    if (rc != 0) {
        child.pid = -1;
        throw Error(ErrorKind::Io, "cannot start '" + argv[0] + "': " + std::strerror(rc));
    }
    ::close(writeEnd.fd);
    writeEnd.fd = -1;

    // Wait for the end, the timeout or a cancel, collecting stderr as it comes.
    ProcessOutcome outcome;
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(timeoutSeconds));
    bool open = true;
    for (;;) {
        if (open) {
            pollfd p{readEnd.fd, POLLIN, 0};
            ::poll(&p, 1, 20);
            open = drain(readEnd.fd, outcome.stderrTail);
        } else {
            ::usleep(20000);
        }
        if (child.ended()) break;
        if (std::chrono::steady_clock::now() >= deadline) {
            outcome.end = ProcessOutcome::End::TimedOut;
            break;
        }
        if (!keepGoing()) {
            outcome.end = ProcessOutcome::End::Stopped;
            break;
        }
    }
    child.finish();
    if (open) drain(readEnd.fd, outcome.stderrTail);
    if (outcome.stderrTail.size() > kTailBytes)
        outcome.stderrTail.erase(0, outcome.stderrTail.size() - kTailBytes);
    if (outcome.end == ProcessOutcome::End::Exited) {
        if (WIFSIGNALED(child.status)) {
            outcome.end = ProcessOutcome::End::Signalled;
            outcome.code = WTERMSIG(child.status);
        } else {
            outcome.code = WEXITSTATUS(child.status);
        }
    }
    return outcome;
}

}  // namespace glint::denoise::detail
