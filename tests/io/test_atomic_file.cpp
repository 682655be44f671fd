#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "io_test_helpers.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io {
namespace {

using test::expect_error;
using test::folder_entries;
using test::read_bytes;
using test::scratch_folder;
using test::write_bytes;

std::vector<std::uint8_t> bytes_of(const std::string& text) {
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

ino_t inode_of(const std::string& path) {
    struct stat status {};
    EXPECT_EQ(::stat(path.c_str(), &status), 0);
    return status.st_ino;
}

TEST(AtomicFile, CommitWritesTheFileAndLeavesNoTemporary) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/out.bin";
    {
        AtomicFile file(path);
        EXPECT_THAT(file.temporary_path(),
                    ::testing::StartsWith(path + ".tmp-" + std::to_string(::getpid()) + "-"));
        EXPECT_TRUE(std::filesystem::exists(file.temporary_path()));
        EXPECT_FALSE(std::filesystem::exists(path));
        file.write(bytes_of("hello "));
        file.write("world", 5);
        file.commit();
        EXPECT_TRUE(file.committed());
    }
    EXPECT_EQ(read_bytes(path), bytes_of("hello world"));
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, TemporaryNamesAreUnique) {
    const std::string folder = scratch_folder();
    AtomicFile first(folder + "/a");
    AtomicFile second(folder + "/a");
    EXPECT_NE(first.temporary_path(), second.temporary_path());
}

TEST(AtomicFile, UncommittedFileLeavesNothing) {
    const std::string folder = scratch_folder();
    {
        AtomicFile file(folder + "/out.bin");
        file.write(bytes_of("partial"));
    }
    EXPECT_TRUE(folder_entries(folder).empty());
}

TEST(AtomicFile, ExceptionBeforeCommitLeavesTheOldFile) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/out.bin";
    write_bytes(path, bytes_of("old"));
    try {
        AtomicFile file(path);
        file.write(bytes_of("new and longer"));
        throw std::runtime_error("simulated failure");
    } catch (const std::runtime_error&) {
    }
    EXPECT_EQ(read_bytes(path), bytes_of("old"));
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, ExistingOutputIsReplacedByRename) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/out.bin";
    write_bytes(path, bytes_of("old contents"));
    const ino_t old_inode = inode_of(path);
    AtomicFile file(path);
    file.write(bytes_of("new"));
    EXPECT_EQ(read_bytes(path), bytes_of("old contents"));  // untouched until commit
    file.commit();
    EXPECT_EQ(read_bytes(path), bytes_of("new"));
    EXPECT_NE(inode_of(path), old_inode);  // a new file renamed over the old one
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, MissingFolderThrows) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/missing/out.bin";
    expect_error([&] { AtomicFile file(path); }, path,
                 "cannot create a temporary file in its folder (No such file or directory)");
    try {
        AtomicFile file(path);
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find(".tmp-"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(folder_entries(folder).empty());
}

TEST(AtomicFile, FailedRenameRemovesTheTemporary) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/target";
    std::filesystem::create_directories(path + "/child");  // a non-empty folder cannot be replaced
    expect_error(
        [&] {
            AtomicFile file(path);
            file.write(bytes_of("data"));
            file.commit();
        },
        path, "cannot replace the file");
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"target"});
    EXPECT_TRUE(std::filesystem::is_directory(path));
}

TEST(AtomicFile, WriteAfterCommitThrows) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/out.bin";
    AtomicFile file(path);
    file.commit();
    expect_error([&] { file.write("x", 1); }, path, "write after commit");
}

TEST(AtomicFile, FailedImageWritesLeaveNoFileAndNoTemporary) {
    const std::string folder = scratch_folder();
    Image image(3, 2, 3, 0.5f);
    expect_error([&] { write_png(folder + "/a.png", image, 12); }, folder + "/a.png",
                 "unsupported PNG bit depth 12");
    Image five_channels;
    five_channels.width = 1;
    five_channels.height = 1;
    five_channels.channels = 5;
    five_channels.pixels.assign(5, 0.0f);
    expect_error([&] { write_exr(folder + "/a.exr", five_channels); }, folder + "/a.exr",
                 "5 channels");
    Image with_nan(2, 2, 1, 0.0f);
    with_nan.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
    expect_error([&] { write_pfm(folder + "/a.pfm", with_nan); }, folder + "/a.pfm",
                 "NaN at texel (1, 1)");
    expect_error([&] { write_png(folder + "/b.png", with_nan, 8); }, folder + "/b.png",
                 "NaN at texel (1, 1)");
    PackedLeanMap empty_map;
    expect_error([&] { write_ktx2(folder + "/a.ktx2", empty_map); }, folder + "/a.ktx2",
                 "without levels");
    // A target that cannot be replaced: the failure happens after the data was written.
    std::filesystem::create_directories(folder + "/busy.png/child");
    expect_error([&] { write_png(folder + "/busy.png", image, 8); }, folder + "/busy.png",
                 "cannot replace the file");
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"busy.png"});
}

TEST(AtomicFile, WritersReplaceAnExistingOutput) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/out.png";
    write_png(path, Image(4, 4, 1, 0.0f), 8);
    write_png(path, Image(3, 5, 3, 1.0f), 16);
    const Image image = read_image(path);
    EXPECT_EQ(image.width, 3);
    EXPECT_EQ(image.height, 5);
    EXPECT_EQ(image.channels, 3);
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"out.png"});
}

TEST(EnsureNotSameFile, RefusesTheSameFileUnderAnyName) {
    const std::string folder = scratch_folder();
    const std::string input = folder + "/in.png";
    write_bytes(input, bytes_of("x"));
    expect_error([&] { ensure_not_same_file(input, input); }, input,
                 "is the same file as the input " + input);
    const std::string spelled = folder + "/./in.png";
    expect_error([&] { ensure_not_same_file(spelled, input); }, spelled, "same file");
    std::filesystem::create_symlink(input, folder + "/link.png");
    expect_error([&] { ensure_not_same_file(folder + "/link.png", input); }, folder + "/link.png",
                 "same file");
    std::filesystem::create_hard_link(input, folder + "/hard.png");
    expect_error([&] { ensure_not_same_file(folder + "/hard.png", input); }, folder + "/hard.png",
                 "same file");
}

TEST(EnsureNotSameFile, AcceptsDifferentOrMissingFiles) {
    const std::string folder = scratch_folder();
    write_bytes(folder + "/a", bytes_of("x"));
    write_bytes(folder + "/b", bytes_of("x"));
    EXPECT_NO_THROW(ensure_not_same_file(folder + "/a", folder + "/b"));
    EXPECT_NO_THROW(ensure_not_same_file(folder + "/new", folder + "/a"));
    EXPECT_NO_THROW(ensure_not_same_file(folder + "/a", folder + "/missing"));
}

TEST(AtomicFile, MappedFileIsWrittenAndReplacesTheOld) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/mapped.bin";
    for (Durability durability : {Durability::Rename, Durability::Flush}) {
        write_bytes(path, bytes_of("old contents"));
        AtomicFile file(path, durability);
        std::uint8_t* bytes = file.map(5);
        ASSERT_NE(bytes, nullptr);
        EXPECT_EQ(bytes[0], 0) << "a newly reserved file reads as zeros";
        std::memcpy(bytes, "abcde", 5);
        EXPECT_EQ(read_bytes(path), bytes_of("old contents")) << "not replaced before commit";
        file.commit();
        EXPECT_EQ(read_bytes(path), bytes_of("abcde"));
        EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"mapped.bin"});
    }
}

TEST(AtomicFile, UncommittedMappedFileLeavesNothing) {
    const std::string folder = scratch_folder();
    {
        AtomicFile file(folder + "/out.bin");
        std::memset(file.map(1 << 20), 7, 1 << 20);
    }
    EXPECT_TRUE(folder_entries(folder).empty());
}

TEST(AtomicFile, MapAndWriteDoNotMix) {
    const std::string folder = scratch_folder();
    AtomicFile written(folder + "/a");
    written.write(bytes_of("x"));
    expect_error([&] { written.map(4); }, folder + "/a", "map of a file already written");
    AtomicFile mapped(folder + "/b");
    mapped.map(4);
    expect_error([&] { mapped.write(bytes_of("x")); }, folder + "/b", "write to a mapped file");
    expect_error([&] { mapped.map(4); }, folder + "/b", "map of a file already written");
    mapped.commit();
    expect_error([&] { mapped.map(4); }, folder + "/b", "map after commit");
}

TEST(AtomicFile, CopiedFileHasTheSourcesBytesAndReplacesTheOld) {
    const std::string folder = scratch_folder();
    const std::string source = folder + "/source.bin";
    const std::string path = folder + "/copy.bin";
    // Larger than the read-and-write pieces (1 MiB), not a multiple of them, every byte value.
    std::vector<std::uint8_t> bytes((3u << 20) + 12345);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = std::uint8_t((i * 2654435761u) >> 13);
    write_bytes(source, bytes);
    for (Durability durability : {Durability::Rename, Durability::Flush}) {
        write_bytes(path, bytes_of("old contents"));
        AtomicFile file(path, durability);
        file.copy_from(source, bytes.size());
        EXPECT_EQ(read_bytes(path), bytes_of("old contents")) << "not replaced before commit";
        file.commit();
        EXPECT_EQ(read_bytes(path), bytes);
        EXPECT_EQ(folder_entries(folder), (std::vector<std::string>{"copy.bin", "source.bin"}));
    }
    // An empty source gives an empty file.
    write_bytes(folder + "/empty", {});
    AtomicFile empty(folder + "/empty.copy");
    empty.copy_from(folder + "/empty", 0);
    empty.commit();
    EXPECT_TRUE(read_bytes(folder + "/empty.copy").empty());
    EXPECT_EQ(read_bytes(source), bytes) << "the source is not modified";
}

TEST(AtomicFile, CopyFromRefusesAWrongSizeAMissingSourceAndAFolder) {
    const std::string folder = scratch_folder();
    const std::string source = folder + "/source.bin";
    write_bytes(source, bytes_of("twelve bytes"));
    {
        AtomicFile file(folder + "/a");
        expect_error([&] { file.copy_from(source, 13); }, source, "holds 12 bytes, not 13");
        expect_error([&] { file.copy_from(folder + "/missing", 1); }, folder + "/missing", "cannot open");
        expect_error([&] { file.copy_from(folder, 0); }, folder, "is not a regular file");
        // Nothing was copied: the file can still be written.
        file.write(bytes_of("x"));
        expect_error([&] { file.copy_from(source, 12); }, folder + "/a", "copy into a file already written");
        file.commit();
        expect_error([&] { file.copy_from(source, 12); }, folder + "/a", "copy after commit");
    }
    EXPECT_EQ(read_bytes(folder + "/a"), bytes_of("x"));
    // A symbolic link is not followed.
    std::filesystem::create_symlink(source, folder + "/link");
    AtomicFile linked(folder + "/b");
    expect_error([&] { linked.copy_from(folder + "/link", 12); }, folder + "/link", "cannot open");
}

TEST(AtomicFile, Ktx2BytesDoNotDependOnThreadsOrDurability) {
    const std::string folder = scratch_folder();
    PackedLeanMap map;
    map.storage = Storage::Unorm16;
    for (int size = 37; size >= 1; size /= 2) {
        PackedLevel level;
        level.width = size;
        level.height = size;
        level.lean1.resize(std::size_t(size) * std::size_t(size) * 8);
        level.lean2.resize(level.lean1.size());
        for (std::size_t i = 0; i < level.lean1.size(); ++i) {
            level.lean1[i] = std::uint8_t(i * 7 + std::size_t(size));
            level.lean2[i] = std::uint8_t(i * 13 + 5);
        }
        map.levels.push_back(std::move(level));
        if (size == 1) break;
    }
    WriteOptions one_thread;
    one_thread.threads = 1;
    WriteOptions two_threads_flushed;
    two_threads_flushed.threads = 2;
    two_threads_flushed.durability = Durability::Flush;
    write_ktx2(folder + "/a.ktx2", map, one_thread);
    write_ktx2(folder + "/b.ktx2", map, two_threads_flushed);
    EXPECT_EQ(read_bytes(folder + "/a.ktx2"), read_bytes(folder + "/b.ktx2"));
    const PackedLeanMap back = read_ktx2(folder + "/b.ktx2");
    ASSERT_EQ(back.levels.size(), map.levels.size());
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        EXPECT_EQ(back.levels[l].lean1, map.levels[l].lean1) << "level " << l;
        EXPECT_EQ(back.levels[l].lean2, map.levels[l].lean2) << "level " << l;
    }
}

}  // namespace
}  // namespace leanfade::io
