// Input files must be regular files. A FIFO given as a probe, configuration, view or
// trace file blocked for ever; /dev/zero or /dev/urandom was read until std::bad_alloc
// without naming the file. Every reader checks its file here before opening it (scene
// files, already checked by their loaders, too).
#pragma once

#include <filesystem>
#include <string>

namespace hrad {

/// A text file's UTF-8 byte-order mark, if it starts with one, removed: editors on
/// Windows write one, and it broke the first line of OBJ, MTL, MGF, probe and view
/// files (JSON parsers skip it already).
std::string without_bom(std::string text);

/// A text file's contents as the readers take them: without_bom, and refused with
/// InputError(file, line, "a NUL byte ...") when the text holds a NUL byte (a binary
/// file; a message quoting the line was cut at the NUL).
std::string checked_text(std::string text, const std::string& file);

/// Throws InputError(path, 0, "... does not exist" / "... is not a regular file (a
/// folder, a FIFO or a device)") unless `path` names a regular file (or a link to one).
/// `what` names the file's role in the message ("the probe file").
void check_input_file(const std::filesystem::path& path, const std::string& what = "the file");

}  // namespace hrad
