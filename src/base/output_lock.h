// Locks on outputs that several processes may write at once: `veil render --frames` into
// one frame pattern (two runs at once left frames of two sizes). One lock file per output
// beside it, ".<output file name>.lock" (the pattern as written), and one byte of it per frame
// under an fcntl write lock, so runs over disjoint frames of one pattern (the slices of a
// Slurm array, scripts/slurm/render-frames.sbatch) go on side by side while a run that would
// write a frame another run is writing is refused before it renders. The kernel releases the
// locks when their process ends, however it ends; a lock file left behind by a killed run
// is taken over by the next. The regress report folder's lock (regress/report_folder.h) is
// the same idea for one whole folder.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace veil {

class OutputLock {
public:
    // Locks `frames` of `output` (none: the whole output, e.g. a video) for `who` (e.g. "veil
    // render"). Throws veil::Error naming the output, the frame, the other run's pid and the
    // lock file when another process holds one of them, and refuses a lock file that is a
    // symbolic link, a hard link or not a regular file (nothing is written through it).
    OutputLock(const std::filesystem::path& output, const std::vector<int>& frames,
               const std::string& who);
    // Releases the locks; removes the lock file when no other process holds part of it.
    ~OutputLock();
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;
    const std::filesystem::path& file() const { return file_; }

    // The lock file of `output`: ".<file name>.lock" in its folder (a name that would pass
    // 255 bytes is shortened and hashed).
    static std::filesystem::path fileFor(const std::filesystem::path& output);

private:
    std::filesystem::path file_;
    int fd_ = -1;
};

} // namespace veil
