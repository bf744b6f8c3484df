// Errors in user input: the one kind of failure that is the user's to fix.
// Everything that catches an InputError prints what() and exits with status 2.
#pragma once
#include <stdexcept>
#include <string>

#include "wavemmlt/quote.h"

namespace wmlt {

class InputError : public std::runtime_error {
public:
    // "file:line: message" (line 0 means "the whole file").
    InputError(const std::string& file, int line, const std::string& message)
        : std::runtime_error(format(file, line, message)), file_(sanitized(file)), line_(line), problem_(sanitized(message)) {}
    explicit InputError(const std::string& message) : std::runtime_error(sanitized(message)), problem_(sanitized(message)) {}

    // Its parts (the Python module's InputError carries them): the file ("" when the
    // message is not about one), the line (0: the whole file) and the problem.
    const std::string& file() const { return file_; }
    int line() const { return line_; }
    const std::string& problem() const { return problem_; }

private:
    std::string file_;
    int line_ = 0;
    std::string problem_;

    // The net under every message: bytes that are not printable (NUL, control characters,
    // invalid UTF-8) shown as \xNN, so a message is one line of text whatever a file held.
    static std::string format(const std::string& file, int line, const std::string& message) {
        if (file.empty()) return sanitized(message);
        if (line > 0) return sanitized(file + ":" + std::to_string(line) + ": " + message);
        return sanitized(file + ": " + message);
    }
};

}  // namespace wmlt
