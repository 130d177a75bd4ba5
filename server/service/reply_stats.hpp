// The X-Surfdeform-Stats of each route, one typed struct per route, turned
// into JSON by ToJson when the HTTP layer writes the header (reply.hpp,
// StatsHeaderText). The field names are the header's.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/animation/animation.hpp"
#include "engine/common/flat_sheet.hpp"
#include "engine/deform/deform.hpp"
#include "meshio/mesh_import.hpp"
#include "part/part_settings.hpp"
#include "part/solid_report.hpp"
#include "proto/api.hpp"
#include "service/reply.hpp"
#include "service/text_models.hpp"

namespace surfdeform {

// POST /v1/surfaces: the surface's id, and whether it was flattened before.
struct SurfaceReplyStats final : ReplyStats {
  std::string surface_id;
  bool cached = false;
  nlohmann::json ToJson() const override;
};

// A mesh answer: how it was encoded (MeshReply sets it).
struct EncodedMeshStats : ReplyStats {
  std::optional<std::string> compression;  // a GLB's
  int pieces = 0;                          // a Draco GLB cut into pieces per group, when > 1

 protected:
  void AddEncoding(nlohmann::json* j) const;
};

// POST /v1/deform, and one frame of POST /v1/animate (`animation`): the
// surface, the model's format, counts, the placement, the subdivision, the
// flattening's quality, warnings, a text's account, and an edit's warm start.
struct DeformReplyStats final : EncodedMeshStats {
  static constexpr size_t kMaxRigidParts = 1000;  // the parts listed ("each")
  std::string surface_id;
  bool cached = false;
  proto::OutputFormat format = proto::OutputFormat::kGlb;
  MeshFormat input_format = MeshFormat::kUnknown;
  std::vector<std::string> input_warnings;  // the import's
  DeformStats deform;
  FlattenQuality quality;
  bool placement_reused = false;    // from the memo: the same model came before
  bool subdivision_reused = false;  // not run: it added nothing to the same model before
  std::shared_ptr<const TextStats> text;
  struct Frame {
    int frame = 0;
    int frames = 0;
    double time = 0.0;
  };
  std::optional<Frame> animation;
  // An edit's warm start (service.cpp, WarmStartJson: the surface reply's
  // account of it, with where the placement went); null: none.
  nlohmann::json warm_start;
  nlohmann::json ToJson() const override;
};

// A deformation's stats: its surface, flattening, input and result (the
// rigid parts' list cut to kMaxRigidParts).
std::shared_ptr<DeformReplyStats> DeformReplyStatsOf(const std::string& surface_id,
                                                     const FlattenQuality& quality, bool hit,
                                                     proto::OutputFormat format,
                                                     const ImportedMesh& imported,
                                                     const DeformStats& deform);

// POST /v1/animate: the model, and each frame's flattening (frame 0 cold,
// the others warm from the one before).
struct AnimationReplyStats final : ReplyStats {
  std::string animation_id;
  bool cached = false;
  std::vector<FrameFlattening> frames;
  double fps = 0.0;
  size_t vertices = 0;
  size_t triangles = 0;
  std::string compression;
  MeshFormat input_format = MeshFormat::kUnknown;
  std::vector<std::string> input_warnings;
  SubdivisionStats subdivision;
  int subdivision_passes = 0;
  DeformStats first_frame;
  std::shared_ptr<const TextStats> text;
  nlohmann::json ToJson() const override;
};

// POST /v1/text: the text's mesh and its account.
struct TextReplyStats final : EncodedMeshStats {
  size_t vertices = 0;
  size_t triangles = 0;
  proto::OutputFormat format = proto::OutputFormat::kGlb;
  std::shared_ptr<const TextStats> text;
  nlohmann::json ToJson() const override;
};

// POST /v1/parts: the part's report (also its body with ?report=json):
// its measures in mm, the checks it passed, its thinnest wall, warnings.
struct PartReplyStats final : EncodedMeshStats {
  proto::OutputFormat format = proto::OutputFormat::k3mf;
  std::string surface_id;  // a body from a stored surface; empty: inline
  std::string model_id;    // an uploaded body
  PartSettings part;
  int nu = 0, nv = 0;  // the body's samples (a body grown from a surface)
  SolidReport solid;
  std::optional<double> thinnest_wall_mm;  // unset: not measured (an uploaded body)
  std::vector<std::string> warnings;
  nlohmann::json ToJson() const override;
};

}  // namespace surfdeform
