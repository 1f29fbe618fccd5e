#include "pipeline/hdf5/file.h"

#include <atomic>
#include <utility>

#include "pipeline/hdf5/detail.h"

namespace fogpipe::hdf5 {

File::File(std::string path, std::unique_ptr<H5::H5File> file)
    : path_(std::move(path)), file_(std::move(file)) {}

namespace {

std::atomic<int> g_abandoned_files{0};

/// Half the number of entries per node of the chunk-index B-tree (H5Pset_istore_k).
constexpr int kChunkIndexK = 4;

/// fogpipe reports HDF5's error stack inside hdf5::Error; the library's own printing to stderr
/// is turned off for the calling thread (per-thread state; the caller holds the lock).
void SilencePrinterLocked() {
  H5::Exception::dontPrint();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

}  // namespace

File File::OpenReadOnly(const std::string& path) {
  SilencePrinterLocked();
  return detail::Checked(path, "", "open read-only", [&] {
    return File(path, std::make_unique<H5::H5File>(path, H5F_ACC_RDONLY));
  });
}

File File::Create(const std::string& path, bool overwrite) {
  SilencePrinterLocked();
  return detail::Checked(path, "", "create file", [&] {
    H5::FileAccPropList access;
    access.setFcloseDegree(H5F_CLOSE_STRONG);
    // The HDF5 1.8 file format, read by every HDF5 since 1.8.0 (h5py, MATLAB since R2011a):
    // small groups keep their links in the group's own header instead of the 1.6 format's
    // symbol-table B-tree and local heap (about 1 KB per group; hdf5 docs, "Groups" / "Link
    // storage"). The upper bound keeps 1.10-only structures out, so older readers still read it.
    access.setLibverBounds(H5F_LIBVER_V18, H5F_LIBVER_V18);
    H5::FileCreatPropList create;
    // The B-tree indexing a chunked dataset's chunks is allocated a node of 2 * kChunkIndexK
    // entries even for one chunk: HDF5's default K = 32 costs ~2.6 KB per chunked dataset, more
    // than deflate saves on a few thousand samples. A node of 8 entries (~0.35 KB) only adds a
    // B-tree level per factor of 8 chunks (3 levels for the ~3700 chunks of 28 columns x 24 h at
    // 100 Hz).
    create.setIstorek(kChunkIndexK);
    return File(path, std::make_unique<H5::H5File>(path, overwrite ? H5F_ACC_TRUNC : H5F_ACC_EXCL,
                                                   create, access));
  });
}

Group File::Root() const {
  if (!file_) throw Error(path_, "/", "open root group", "file is closed", "");
  return detail::Checked(path_, "/", "open root group",
                         [&] { return Group(path_, "/", file_->openGroup("/")); });
}

void File::Flush() {
  if (!file_) throw Error(path_, "", "flush", "file is closed", "");
  detail::Checked(path_, "", "flush", [&] { file_->flush(H5F_SCOPE_GLOBAL); });
}

void File::Close() {
  if (!file_) return;
  try {
    detail::Checked(path_, "", "close", [&] { file_->close(); });
  } catch (...) {
    // HDF5 1.10 frees part of a file whose close failed (a write error while flushing: ENOSPC,
    // EFBIG) yet keeps its id; the second H5Fclose that ~H5File would issue dereferences freed
    // memory (SIGSEGV in H5F__close). The object is therefore never destroyed: a few hundred
    // bytes and one descriptor per failed file, against a crash of the process.
    new std::shared_ptr<H5::H5File>(std::move(file_));
    ++g_abandoned_files;
    throw;
  }
  file_.reset();
}

int AbandonedFiles() { return g_abandoned_files.load(); }

hid_t File::id() const { return file_ ? file_->getId() : -1; }

}  // namespace fogpipe::hdf5
