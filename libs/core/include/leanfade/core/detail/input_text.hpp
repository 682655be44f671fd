#pragma once
// Text read from input files: the one reader of whole text files (presets, OBJ meshes, result
// tables), and the escaping of file text before it reaches a message or printed output.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace leanfade {

// Largest text inputs read whole into memory.
inline constexpr std::uint64_t kMaxPresetFileBytes = std::uint64_t(1) << 20;        // 1 MiB
inline constexpr std::uint64_t kMaxResultsFileBytes = std::uint64_t(256) << 20;     // 256 MiB
inline constexpr std::uint64_t kMaxObjFileBytes = std::uint64_t(1) << 30;           // 1 GiB

// Reads the whole of a regular file of at most `max_bytes` bytes. `kind` names what the file
// should be, with its article ("a preset file"), in the messages. Throws leanfade::Error(path,
// cause): "file not found", "cannot open (<reason>)", "is a directory, not <kind>", "is not a
// regular file" (a FIFO, device or socket, never read: a FIFO without a writer cannot hang it,
// /dev/zero cannot make it grow), "file of N bytes exceeds the limit of M bytes for <kind>",
// "read error (<reason>)". The size is checked before anything is allocated, and a file that
// grows while it is read is cut at the size it had when opened.
std::string read_regular_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& kind);

// The files this run will replace, as every reader sees them. io::OutputPlan::check() claims
// each output that exists already (its device and inode); every reader of input files
// (read_regular_file, io's InputFile, the glTF loader) asks claimed_output() about each file it
// opens, before reading a byte of it, and refuses one that is an output of the run: a file that
// another file names (a glTF's LEANFADE_lean_map, an OBJ's .mtl and textures, the levels of a
// MIP series) is an input of the run too, whether or not the plan's list of inputs had it.
void claim_output_file(std::uint64_t device, std::uint64_t inode, const std::string& output);
// The name of the output claimed for the file (device, inode), or "" when it is none.
std::string claimed_output(std::uint64_t device, std::uint64_t inode);
// The cause of the refusal of `path`, an input that is the output `output` of the run.
std::string claimed_output_cause(const std::string& output);

// True when `path`, every symbolic link of it resolved, lies inside `folder` (resolved too; ""
// is the working folder). A path that does not exist yet is judged on the part that does. For
// the files one input names (an OBJ's .mtl and textures, a shader's #include): their names are
// checked on their spelling, and this checks where they lead, before any byte is read, so that a
// link inside the folder to a file outside it is refused and none of that file's text reaches a
// message.
bool resolves_inside(const std::string& path, const std::string& folder);

// `text` made safe for a one-line message or a terminal: printable ASCII and valid UTF-8
// sequences of printable characters stay as they are; control characters (newlines and escape
// sequences included), C1 controls, bidirectional overrides, invalid UTF-8 and backslashes are
// written as \xNN, one per byte. Longer results are cut after `max_bytes` of output and end
// with "...".
std::string escape_text(std::string_view text, std::size_t max_bytes = 200);

// `text` as one line for a terminal, whole: control characters (newline, carriage return, NUL,
// ESC, BEL, ...) and bytes of invalid UTF-8 as \xNN, C1 controls and the code points that change
// how a line reads (bidirectional marks, embeddings, overrides and isolates, line and paragraph
// separators, zero-width and other invisible format characters) as \u{NNNN}. Backslashes stay
// (text already passed through escape_text keeps its form). Every message the command line prints
// goes through it.
std::string terminal_text(std::string_view text);

}  // namespace leanfade
