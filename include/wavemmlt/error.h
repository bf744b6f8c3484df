// Errors in user input: the one kind of failure that is the user's to fix.
// Everything that catches an InputError prints what() and exits with status 2.
#pragma once
#include <stdexcept>
#include <string>

namespace wmlt {

class InputError : public std::runtime_error {
public:
    // "file:line: message" (line 0 means "the whole file").
    InputError(const std::string& file, int line, const std::string& message)
        : std::runtime_error(format(file, line, message)) {}
    explicit InputError(const std::string& message) : std::runtime_error(message) {}

private:
    static std::string format(const std::string& file, int line, const std::string& message) {
        if (file.empty()) return message;
        if (line > 0) return file + ":" + std::to_string(line) + ": " + message;
        return file + ": " + message;
    }
};

}  // namespace wmlt
