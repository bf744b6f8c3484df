// Child processes for the end-to-end tests of the viewers (test_view.cpp,
// test_display_server.cpp): an environment changed per child, stdout and stderr in files,
// and waits with a timeout that kill what overruns, so no test can hang.
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace child {

using Clock = std::chrono::steady_clock;
constexpr double kLimit = 60;  // seconds a test lets any child run before it kills it

inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline std::string readText(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

class Process {
public:
    Process() = default;
    explicit Process(pid_t pid) : pid_(pid) {}
    Process(Process&& o) noexcept : pid_(o.pid_), status_(o.status_) { o.pid_ = -1; }
    Process& operator=(Process&& o) noexcept {
        std::swap(pid_, o.pid_);
        std::swap(status_, o.status_);
        return *this;
    }
    ~Process() { kill(SIGKILL); }

    bool started() const { return pid_ > 0; }
    bool running() {
        if (pid_ <= 0) return false;
        int st = 0;
        const pid_t r = waitpid(pid_, &st, WNOHANG);
        if (r == 0) return true;
        status_ = (r == pid_ && WIFEXITED(st)) ? WEXITSTATUS(st) : -1;
        pid_ = -1;
        return false;
    }
    // The exit status (-1: ended by a signal); a process still running after `seconds` is
    // killed and -2 returned.
    int wait(double seconds) {
        const auto t0 = Clock::now();
        while (running()) {
            if (since(t0) > seconds) {
                kill(SIGKILL);
                return -2;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return status_;
    }
    void kill(int signal) {
        if (pid_ <= 0) return;
        ::kill(pid_, signal);
        if (signal == SIGKILL) {
            waitpid(pid_, nullptr, 0);
            pid_ = -1;
        }
    }

private:
    pid_t pid_ = -1;
    int status_ = -1;
};

// Starts argv[0] (looked up in PATH) with this process's environment changed by `env`:
// "NAME=value" sets NAME, "NAME" alone removes it. stdout and stderr go to the files named
// (empty: /dev/null). Returns a Process that has not started when the spawn failed.
inline Process spawn(const std::vector<std::string>& argv, const std::vector<std::string>& env = {}, const std::string& out = "",
                     const std::string& err = "") {
    std::vector<std::string> vars;
    for (char** e = environ; *e; ++e) {
        const std::string v = *e;
        bool replaced = false;
        for (const std::string& change : env) {
            const std::string name = change.substr(0, change.find('='));
            replaced |= v.compare(0, name.size() + 1, name + "=") == 0;
        }
        if (!replaced) vars.push_back(v);
    }
    for (const std::string& change : env)
        if (change.find('=') != std::string::npos) vars.push_back(change);
    std::vector<char*> a, e;
    for (const std::string& s : argv) a.push_back(const_cast<char*>(s.c_str()));
    for (const std::string& s : vars) e.push_back(const_cast<char*>(s.c_str()));
    a.push_back(nullptr);
    e.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out.empty() ? "/dev/null" : out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err.empty() ? "/dev/null" : err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    const int rc = posix_spawnp(&pid, a[0], &fa, nullptr, a.data(), e.data());
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? Process(pid) : Process();
}

// Runs a command to its end (killed after `seconds`) and returns its standard output.
inline std::string output(const std::vector<std::string>& argv, const std::vector<std::string>& env = {}, double seconds = 10) {
    char path[] = "/tmp/wmlt-child-out-XXXXXX";
    const int fd = mkstemp(path);
    if (fd < 0) return "";
    close(fd);
    Process p = spawn(argv, env, path);
    p.wait(seconds);
    const std::string text = readText(path);
    unlink(path);
    return text;
}

}  // namespace child
