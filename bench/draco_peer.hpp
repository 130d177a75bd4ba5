// The peer of the service benchmark: Draco's own encoder on the service's
// output mesh, read by Draco's own PLY reader from the service's PLY output
// (our trusted bytes), so that it sees the same vertex order as the
// service's encoder did. (A mesh decoded from the .drc is in edgebreaker
// order and encodes ~20% faster: not the same work.) In its own translation
// unit, apart from httplib.h.
#pragma once

#include <string>

namespace surfdeform::bench {

// Draco's encoder with the service's default settings (14/10/12/8 bits,
// speed 5, edgebreaker) on a mesh read from PLY bytes.
class DracoPeer {
 public:
  explicit DracoPeer(const std::string& ply);
  ~DracoPeer();
  bool ok() const;
  double EncodeMs();  // one encoding, timed
  // One encoding into `out` (the .drc bytes); false if Draco failed.
  bool Encode(std::string* out);

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace surfdeform::bench
