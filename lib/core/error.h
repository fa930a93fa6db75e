#pragma once
// Errors a user can cause. The message is complete and printed as-is by the tools:
// it names the file, the key or line, and what is allowed.
#include <stdexcept>
#include <string>

namespace vpm {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Bad configuration: "<file>:<line>: <key>: <message>".
class ConfigError : public Error {
public:
    using Error::Error;
};

// A file that cannot be read, or whose contents are wrong: "<file>: <message>".
class FileError : public Error {
public:
    using Error::Error;
};

}  // namespace vpm
