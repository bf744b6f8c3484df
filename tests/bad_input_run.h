// The bad-input tests' harness (test_bad_input.cpp, test_bad_input_bounds.cpp): runs the
// `wavemmlt` binary as a child with its stdout and stderr in files, its wall time and peak
// resident memory measured and bounded, and checks what a user must see of bad input: exit
// status 2, one line "error: ..." holding the expected fragments, no output and no
// temporary file.
#pragma once
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <grp.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace badinput {

namespace fs = std::filesystem;

const std::string kBin = WAVEMMLT_BIN;

using Clock = std::chrono::steady_clock;

struct TempDir {
    fs::path path;
    TempDir() {
        static int count = 0;
        path = fs::temp_directory_path() / ("wmlt-badinput-" + std::to_string(getpid()) + "-" + std::to_string(count++));
        fs::remove_all(path);
        fs::create_directories(path);
        fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
    }
    ~TempDir() {
        std::error_code ec;
        for (auto& e : fs::recursive_directory_iterator(path, ec))  // read-only folders made in a test
            fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
    std::string write(const std::string& name, const std::string& bytes) const {
        std::ofstream(path / name, std::ios::binary) << bytes;
        return file(name);
    }
    // Files whose name marks them as a temporary of an interrupted write.
    int temporaries() const {
        int n = 0;
        std::error_code ec;
        for (auto& e : fs::recursive_directory_iterator(path, ec))
            if (e.path().filename().string().find(".tmp-") != std::string::npos) ++n;
        return n;
    }
};

inline std::string readFile(const std::string& path, size_t limit = std::numeric_limits<size_t>::max()) {
    std::ifstream f(path, std::ios::binary);
    std::string s(std::min<size_t>(limit, 1 << 20), '\0');
    f.read(s.data(), std::streamsize(s.size()));
    s.resize(size_t(f.gcount()));
    return s;
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

struct Proc {
    int status = -1;      // exit status, -1 when killed
    bool killed = false;  // by the watchdog below
    std::string why;      // why it was killed
    std::string err;      // stderr (its first 1 MiB)
    size_t errBytes = 0;  // the size of all of stderr
    double seconds = 0;   // wall time
    long maxRssKb = 0;    // peak resident memory of this process alone (wait4)
};

struct Limits {
    double seconds = 60;    // killed after this long
    long rssKb = 0;         // killed when its resident memory exceeds this (0: no limit)
    bool asNobody = false;  // run as uid/gid 65534 (to test permissions when root)
};

// Runs `wavemmlt args...` (no shell), stdout and stderr to files in `dir`, watching its
// wall time and resident memory (/proc/<pid>/status, every 5 ms).
inline Proc run(const std::vector<std::string>& args, const TempDir& dir, Limits lim = Limits()) {
    const std::string outPath = dir.file("stdout.txt"), errPath = dir.file("stderr.txt");
    std::vector<std::string> a = {kBin};
    a.insert(a.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& s : a) argv.push_back(s.data());
    argv.push_back(nullptr);
    const int outFd = open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    const int errFd = open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    REQUIRE(outFd >= 0);
    REQUIRE(errFd >= 0);
    const auto t0 = Clock::now();
    const pid_t pid = fork();
    if (pid == 0) {  // only async-signal-safe calls until exec
        dup2(outFd, 1);
        dup2(errFd, 2);
        signal(SIGINT, SIG_DFL);
        if (lim.asNobody && (setgroups(0, nullptr) != 0 || setgid(65534) != 0 || setuid(65534) != 0)) _exit(126);
        execv(kBin.c_str(), argv.data());
        _exit(127);
    }
    close(outFd);
    close(errFd);
    REQUIRE(pid > 0);
    Proc p;
    int st = 0;
    rusage ru{};
    while (true) {
        const pid_t done = wait4(pid, &st, WNOHANG, &ru);
        if (done == pid) break;
        const double t = std::chrono::duration<double>(Clock::now() - t0).count();
        long rss = 0;
        std::ifstream status("/proc/" + std::to_string(pid) + "/status");
        for (std::string line; std::getline(status, line);)
            if (line.rfind("VmRSS:", 0) == 0) rss = std::atol(line.c_str() + 6);
        if (!p.killed && (t > lim.seconds || (lim.rssKb > 0 && rss > lim.rssKb))) {
            p.killed = true;
            p.why = t > lim.seconds ? "ran longer than " + std::to_string(lim.seconds) + " s"
                                    : "resident memory " + std::to_string(rss) + " KiB exceeded " + std::to_string(lim.rssKb) + " KiB";
            kill(pid, SIGKILL);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    p.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    p.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    p.maxRssKb = ru.ru_maxrss;
    std::error_code ec;
    p.errBytes = size_t(fs::file_size(errPath, ec));
    p.err = readFile(errPath, 1 << 20);
    return p;
}

// The common requirements: exit 2, one line "error: ..." holding every fragment, no
// output image and no temporary file. `out` is the output image the command names.
inline void requireBad(const Proc& p, const std::vector<std::string>& fragments, const std::string& out, const TempDir& dir) {
    INFO("stderr: " << p.err.substr(0, 2000) << (p.killed ? "\nkilled: " + p.why : ""));
    CHECK_FALSE(p.killed);
    CHECK(p.status == 2);
    CHECK(p.err.rfind("error: ", 0) == 0);
    CHECK(std::count(p.err.begin(), p.err.end(), '\n') == 1);  // one message, one line
    for (const std::string& f : fragments) CHECK(contains(p.err, f));
    CHECK_FALSE(fs::exists(out));
    CHECK(dir.temporaries() == 0);
}
// A PFM of w x h pixels, all `v`.
inline std::string pfm(int w, int h, float v) {
    std::string s = "PF\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
    for (int i = 0; i < 3 * w * h; ++i) s.append(reinterpret_cast<const char*>(&v), 4);
    return s;
}

}  // namespace badinput
