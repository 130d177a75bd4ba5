// The texts of the text benchmark, the same in its C++ side and its peer
// (bench/text_peer/peer.mjs reads them from text_bench's output).
#pragma once

namespace surfdeform::bench {

// A 40-character line and a 200-character paragraph (one line each).
inline constexpr const char* kTextLine = "Sphinx of black quartz, judge my vow now";
inline constexpr const char* kTextParagraph =
    "Ada Lovelace wrote in 1843 that the Analytical Engine might compose elaborate pieces of "
    "music of any degree of complexity or extent, weaving algebraical patterns as the Jacquard "
    "loom weaves flowers...";

}  // namespace surfdeform::bench
