// Runs a program without a shell, for the tests and the bench: posix_spawn with stdout and
// stderr sent to files, then the exit code; or on a pseudo-terminal (forkpty), for what a
// program draws only for a person watching. Header-only.
#pragma once

#include <fcntl.h>
#include <pty.h>
#include <unistd.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

extern char** environ;

namespace msmcl::testing {

/// run_process's result when the program could not be started.
inline constexpr int process_not_started = -2;

/// Runs arguments[0] (a path) with `arguments`; stdout into `out_path` and stderr into
/// `err_path` (created or truncated; "/dev/null" discards, empty keeps this process's),
/// with `environment` ("NAME=VALUE" strings) or, when null, this process's environment.
/// Returns the exit code, -1 when the program did not exit normally (a signal), or
/// process_not_started.
inline int run_process(std::vector<std::string> arguments, const std::string& out_path,
                       const std::string& err_path, const std::vector<std::string>* environment = nullptr) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (!out_path.empty())
        posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (!err_path.empty())
        posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> argv;
    for (std::string& argument : arguments) argv.push_back(argument.data());
    argv.push_back(nullptr);
    std::vector<std::string> variables = environment ? *environment : std::vector<std::string>{};
    std::vector<char*> envp;
    for (std::string& variable : variables) envp.push_back(variable.data());
    envp.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environment ? envp.data() : environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return process_not_started;
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs `argv` with stdin, stdout and stderr on a new pseudo-terminal and `variable` set;
// returns everything it wrote there and its exit code. Independent of the test's own stdin
// (CI has none), unlike util-linux `script`.
inline std::pair<std::string, int> run_on_terminal(const std::vector<std::string>& argv, const char* variable) {
    int master = -1;
    const pid_t child = ::forkpty(&master, nullptr, nullptr, nullptr);
    if (child < 0) return {"forkpty failed", -1};
    if (child == 0) {
        ::putenv(const_cast<char*>(variable));
        std::vector<char*> arguments;
        for (const std::string& a : argv) arguments.push_back(const_cast<char*>(a.c_str()));
        arguments.push_back(nullptr);
        ::execv(arguments[0], arguments.data());
        ::_exit(127);
    }
    // Read until the child's side closes (EIO on Linux once the child has exited).
    std::string text;
    char buffer[4096];
    for (;;) {
        const ssize_t n = ::read(master, buffer, sizeof buffer);
        if (n > 0) text.append(buffer, static_cast<std::size_t>(n));
        else if (n < 0 && errno == EINTR) continue;
        else break;
    }
    ::close(master);
    int status = 0;
    ::waitpid(child, &status, 0);
    return {text, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

} // namespace msmcl::testing
