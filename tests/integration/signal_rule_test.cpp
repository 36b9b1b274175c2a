// One signal rule for every command-line tool (docs/reliability.md, "Signals"): a SIGINT the tool
// was started with ignored (a background job of a non-interactive shell, nohup) stays ignored,
// and the tool finishes its work; otherwise SIGINT removes the tool's temporary files and kills
// it as the signal would. `glint-render`, `apply`, `auto` and `paint` used to die of an ignored
// SIGINT, while `bank` and `glint-image` installed no handler at all.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_boundary.h"
#include "cli_fixture.h"

namespace fs = std::filesystem;

namespace {

/// The signals a process catches (SigCgt of /proc/PID/status); 0 once it is gone.
unsigned long long caughtSignals(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("SigCgt:", 0) == 0) return std::stoull(line.substr(7), nullptr, 16);
    return 0;
}

bool catches(unsigned long long mask, int sig) {
    return (mask >> (sig - 1)) & 1u;
}

class SignalRule : public glint::testing::CliFixture {
  protected:
    SignalRule() : CliFixture("glint-render") {}

    void SetUp() override {
        CliFixture::SetUp();
        bin = m_binary.parent_path();
        // A 160 × 160 Cornell box: every command below takes long enough to be interrupted.
        std::ofstream(m_dir / "scene.json")
            << R"({"camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0],
                   "fovY": 39.3}, "film": {"width": 160, "height": 160},
                   "shapes": [{"obj": ")"
            << GLINT_SOURCE_DIR << R"(/scenes/cornell/cornell_box.obj"}],
                   "render": {"spp": 4, "maxDepth": 4}})";
        ASSERT_EQ(run(path("scene.json") + " --out " + path("in.exr")).exitCode, 0);
        std::ofstream(m_dir / "strokes.json")
            << R"({"layers": [{"filter": "nlmeans"}, {"filter": "bilateral"}],
                   "edits": [{"weights": {"layer": 1, "value": 1}}]})";
    }

    /// Starts `tool args` in the test's folder, with SIGINT ignored when `ignoreSigint`; waits
    /// until the tool has installed its signal rule (it catches SIGTERM), sends SIGINT and
    /// returns the wait status. Fails when the tool ends before it could be interrupted.
    int interrupt(const std::string& tool, const std::vector<std::string>& args,
                  bool ignoreSigint) {
        const pid_t child = fork();
        if (child == 0) {
            if (::chdir(m_dir.c_str()) != 0) _exit(126);
            if (ignoreSigint) ::signal(SIGINT, SIG_IGN);
            if (!std::freopen("stderr.txt", "w", stderr) || !std::freopen("/dev/null", "w", stdout))
                _exit(126);
            const std::string binary = (bin / tool).string();
            std::vector<char*> argv{const_cast<char*>(binary.c_str())};
            for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            ::execv(binary.c_str(), argv.data());
            _exit(127);
        }
        EXPECT_GT(child, 0);
        int status = 0;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < deadline) {
            if (catches(caughtSignals(child), SIGTERM)) {
                ::kill(child, SIGINT);
                ::waitpid(child, &status, 0);
                return status;
            }
            if (::waitpid(child, &status, WNOHANG) == child) {
                ADD_FAILURE() << tool << " ended (status " << status
                              << ") before it caught SIGTERM: it has no signal rule";
                return status;
            }
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        ::kill(child, SIGKILL);
        ::waitpid(child, &status, 0);
        ADD_FAILURE() << tool << " never caught SIGTERM";
        return status;
    }

    /// Temporary files (".NAME.tmp-PID.EXT") left in the test's folder.
    std::vector<std::string> temporaries() const {
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(m_dir))
            if (e.path().filename().string().find(".tmp-") != std::string::npos)
                left.push_back(e.path().filename().string());
        return left;
    }

    fs::path bin;
};

struct Command {
    std::string tool;
    std::vector<std::string> args;
    std::string output;  ///< what a finished run writes
};

std::vector<Command> commands() {
    return {
        {"glint-render",
         {"scene.json", "--spp", "64", "--threads", "1", "--out", "r.exr"},
         "r.exr"},
        {"glint-image", {"diff", "in.exr", "--reference", "in.exr", "--metric", "ssim"}, ""},
        {"glint-denoise", {"apply", "in.exr", "--filter", "nlmeans", "--out", "a.exr"}, "a.exr"},
        {"glint-denoise", {"auto", "in.exr", "--out", "auto.exr"}, "auto.exr"},
        {"glint-denoise", {"bank", "in.exr", "--out", "bank", "--size", "4"}, "bank/index.json"},
        {"glint-denoise",
         {"paint", "in.exr", "--script", "strokes.json", "--save", "p.glint-session.json"},
         "p.glint-session.json"},
    };
}

TEST_F(SignalRule, EveryToolKeepsAnIgnoredSigintAndFinishesItsWork) {
    for (const Command& c : commands()) {
        SCOPED_TRACE(c.tool + " " + c.args.front());
        const int status = interrupt(c.tool, c.args, true);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
            << "status " << status << "\n"
            << glint::testing::slurp(m_dir / "stderr.txt");
        if (!c.output.empty()) {
            EXPECT_TRUE(fs::exists(m_dir / c.output));
        }
        EXPECT_TRUE(temporaries().empty());
    }
}

TEST_F(SignalRule, EveryToolDiesOfASigintItWasNotStartedIgnoringAndLeavesNoTemporary) {
    for (const Command& c : commands()) {
        SCOPED_TRACE(c.tool + " " + c.args.front());
        const int status = interrupt(c.tool, c.args, false);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
        if (!c.output.empty()) {
            EXPECT_FALSE(fs::exists(m_dir / c.output));
        }
        EXPECT_TRUE(temporaries().empty());
    }
}

/// Runs `body` in a forked child and returns its wait status (the child never returns).
template <class Body>
int inChild(Body body) {
    const pid_t pid = fork();
    if (pid == 0) {
        body();
        _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
}

TEST(SignalTemporaries, TheHandlerRemovesWhatWasRegisteredFilesBeforeTheirFolderInOrder) {
    const fs::path dir =
        fs::temp_directory_path() / ("glint_signal_order_" + std::to_string(getpid()));
    fs::remove_all(dir);
    const int status = inChild([&] {
        // As Session::temporaries gives them: the folder's files first, the folder last.
        fs::create_directories(dir / "folder");
        std::vector<std::string> paths;
        for (int i = 0; i < 3; ++i) {
            const fs::path f = dir / "folder" / ("f" + std::to_string(i));
            std::ofstream(f) << i;
            paths.push_back(f.string());
        }
        paths.push_back((dir / "folder").string());
        glint::cli::removeOnSignal(paths);
        raise(SIGTERM);
    });
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
    EXPECT_FALSE(fs::exists(dir / "folder"));
    fs::remove_all(dir);
}

// A signal may arrive while a registration is under way (the first one used to initialise a
// function-local static, and a handler arriving then re-entered its guard and hung for ever).
// Children register in a loop while the parent signals them after 0-2 ms: each must die of the
// signal at once and leave none of its files. A probe, not a proof: the window is short; the
// list's head is constinit (cli_boundary.h), which the compiler checks.
TEST(SignalTemporaries, ASignalDuringRegistrationsKillsTheChildAndLeavesNoneOfItsFiles) {
    const fs::path dir =
        fs::temp_directory_path() / ("glint_signal_race_" + std::to_string(getpid()));
    for (int round = 0; round < 40; ++round) {
        fs::remove_all(dir);
        fs::create_directories(dir);
        int ready[2];
        ASSERT_EQ(pipe(ready), 0);
        const pid_t pid = fork();
        if (pid == 0) {
            close(ready[0]);
            glint::cli::installSignalRule();
            const char go = 1;
            if (write(ready[1], &go, 1) != 1) _exit(3);
            for (int i = 0;; ++i) {
                const fs::path f = dir / ("f" + std::to_string(i % 64));
                std::ofstream(f) << i;
                glint::cli::removeOnSignal({f.string()});
            }
        }
        close(ready[1]);
        char go = 0;
        ASSERT_EQ(read(ready[0], &go, 1), 1);
        close(ready[0]);
        std::this_thread::sleep_for(std::chrono::microseconds(50 * round));
        kill(pid, SIGTERM);
        int status = 0;
        bool reaped = false;
        for (int waited = 0; waited < 500 && !reaped; ++waited) {
            reaped = waitpid(pid, &status, WNOHANG) == pid;
            if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        if (!reaped) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            FAIL() << "round " << round << ": the child still ran 5 s after SIGTERM";
        }
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM)
            << "round " << round << ", status " << status;
        // A file being written when the signal came may not be registered yet; every
        // registered one is gone, so at most the last one created remains.
        int left = 0;
        for (const auto& e : fs::directory_iterator(dir)) left += e.is_regular_file() ? 1 : 0;
        EXPECT_LE(left, 1) << "round " << round;
    }
    fs::remove_all(dir);
}

}  // namespace
