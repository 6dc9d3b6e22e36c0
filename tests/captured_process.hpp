// Runs a program for the command-line tests (no shell) and reads back what it printed.
#pragma once

#include "io/atomic_file.hpp"
#include "process.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace msmcl::testing {

/// A finished program: its exit code (-1: ended by a signal) and what it wrote.
struct ProcessResult {
    int exit_code = -1;
    std::string out, err;
};

/// Runs arguments[0] with `arguments`, stdout into `out_log` and stderr into `err_log`, and
/// reads both back; a test failure (and exit code -1) when the program cannot be started.
inline ProcessResult run_captured(std::vector<std::string> arguments, const std::string& out_log,
                                  const std::string& err_log) {
    const std::string program = arguments[0];
    const int exit_code = run_process(std::move(arguments), out_log, err_log);
    ProcessResult result;
    if (exit_code == process_not_started) {
        ADD_FAILURE() << "cannot run " << program;
        return result;
    }
    result.exit_code = exit_code;
    result.out = msmcl::io::read_whole_file(out_log);
    result.err = msmcl::io::read_whole_file(err_log);
    return result;
}

} // namespace msmcl::testing
