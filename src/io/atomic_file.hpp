// Whole files read and written. Output files are written to a temporary file
// beside the target and renamed over it, so a failure never leaves a
// half-written file or clobbers an older one.
#pragma once

#include <string>

namespace massid {

// The bytes of the file at `path`; InputError "PATH: ERROR" when it cannot be opened.
std::string read_file(const std::string& path, const char* error = "cannot open file");

// Throws InputError naming the path when the file cannot be written.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace massid
