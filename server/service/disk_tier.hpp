// The second level of the stores on this machine's disk: uploads (models)
// and flattened surfaces outlive a restart, or a kill -9, of a server
// without Redis (docs/RELIABILITY.md, item 37).
//
// A content-addressed directory: each value is a file named by the SHA-256
// of its key, under objects/<first two hex digits>/. A file holds a header
// (a magic line, the value's length and SHA-256, the key) and the value.
//
// - Written atomically: to tmp/, flushed to the disk (fsync), then renamed
//   into place (and the directory flushed), so that a crash leaves either
//   the whole value or none.
// - Checked when read: a file whose magic, length, key or digest does not
//   match is removed and counted as corrupt, never trusted.
// - Bounded: past `budget_bytes` the least recently used files are removed
//   (an index in memory, rebuilt from the directory at start, by each
//   file's modification time, which a read renews).
//
// One process owns a directory (a lock file, held while it runs); a second
// server on the same directory is refused at start.
#pragma once

#include <memory>
#include <string>

#include "base/status.hpp"
#include "service/shared_tier.hpp"

namespace surfdeform {

struct DiskTierOptions {
  std::string dir;                   // created when missing
  size_t budget_bytes = 1ull << 30;  // the files' bytes, in all
};

// kInvalidArgument when the directory cannot be made, written or locked.
Result<std::unique_ptr<SharedTier>> CreateDiskTier(const DiskTierOptions& options);

}  // namespace surfdeform
