#pragma once
// The platform layer: the few calls of leanfade_core and leanfade_io that are specific to Linux,
// each with a portable fallback. The build compiles one implementation (README, "Platforms"):
//   src/platform_linux.cpp     Linux: madvise (transparent huge pages), posix_fallocate + mmap
//                              (mapped output files), getdents64 (removing a folder tree from a
//                              signal handler), FICLONE + copy_file_range (file copies in the
//                              kernel, shared blocks where the file system has them);
//   src/platform_portable.cpp  any other system, or Linux with -DLEANFADE_PORTABLE=ON: ordinary
//                              allocation, memory buffers written with ordinary writes, and
//                              no folder listing in a signal handler.
// Everything else in core and io is standard C++ (std::filesystem included) or POSIX.1.
// Internal to the libraries: not part of the API of <leanfade/leanfade.hpp>.
#include <cstddef>
#include <cstdint>

namespace leanfade::platform {

// Advises [data, data + bytes) (whole pages, page-aligned) to use transparent huge pages. Best
// effort; nothing in the portable implementation.
void advise_huge_pages(void* data, std::size_t bytes) noexcept;

// An output file's bytes in memory, filled by the caller and put in the file by
// finish_output_mapping. Linux: the file's pages mapped shared (their disk space reserved first),
// portable: a zero-filled buffer written to the file when kept.
struct OutputMapping {
    std::uint8_t* bytes = nullptr;  // nullptr on failure
    bool reserve_failed = false;    // failure: the disk space could not be reserved
    int error_number = 0;           // failure: the errno value
};

// Maps `size` (> 0) bytes of the empty file open for reading and writing as `descriptor`. Its
// bytes read as zeros until written.
OutputMapping map_output_file(int descriptor, std::size_t size) noexcept;

// Ends a mapping of map_output_file. keep: its bytes must be in the file afterwards (returns 0,
// or the errno value of a failed write); otherwise they are discarded. Either way the memory is
// released.
int finish_output_mapping(int descriptor, const OutputMapping& mapping, std::size_t size,
                          bool keep) noexcept;

// Whether remove_tree_signal_safe can remove a folder's contents (Linux) or only an empty folder
// (portable: listing a folder is not async-signal-safe there).
bool removes_folder_trees_on_signals() noexcept;
// Copies the first `size` bytes of the file open for reading as `from` (at offset 0) to the
// empty file open for writing as `to`, which ends up with exactly those bytes. Linux: the
// file system shares the blocks where it can (FICLONE: Btrfs, XFS, ...), else reserves the
// destination's blocks (posix_fallocate: a full disk fails first) and the kernel copies them
// (copy_file_range), else read and write; portable: read and write. Returns 0, or the
// errno value of the failure (EIO when `from` has fewer than `size` bytes).
int copy_file_contents(int from, int to, std::uint64_t size) noexcept;

// Removes `path`: a file, or a folder with what it holds (at most `depth` levels down) where
// removes_folder_trees_on_signals(), otherwise an empty folder. Async-signal-safe: no allocation,
// only system calls.
void remove_tree_signal_safe(const char* path, int depth) noexcept;

}  // namespace leanfade::platform
