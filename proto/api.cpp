#include "proto/api.hpp"

#include "base/format.hpp"

#include <type_traits>

#include "proto/content_hash.hpp"
#include "proto/json_object.hpp"
#include "proto/surface_json.hpp"
#include "proto/text_json.hpp"

namespace surfdeform::proto {
namespace {

using nlohmann::json;

template <typename E, size_t N>
std::string EnumName(const EnumEntry<E> (&table)[N], E value) {
  return std::string(NameOf<E>(table, value));
}

// A spec of `kind` with every field at its default ("nurbs": rational).
SurfaceSpec EmptySpec(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::kBezier:
      return BezierSpec{};
    case SurfaceKind::kBSpline:
    case SurfaceKind::kNurbs: {
      BSplineSpec s;
      s.rational = kind == SurfaceKind::kNurbs;
      return s;
    }
    case SurfaceKind::kCylinder:
      return CylinderSpec{};
    case SurfaceKind::kCone:
      return ConeSpec{};
    case SurfaceKind::kSphere:
      return SphereSpec{};
    case SurfaceKind::kTorus:
      return TorusSpec{};
    case SurfaceKind::kWave:
      return WaveSpec{};
    case SurfaceKind::kGrid:
      return GridSpec{};
    case SurfaceKind::kMesh:
      return MeshSpec{};
  }
  return BezierSpec{};
}

Result<SurfaceSpec> ReadSurface(const json& value, const std::string& path) {
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(value, path));
  if (o.Find("kind") == nullptr) {
    std::string names;
    for (const auto& e : kSurfaceKinds) names += (names.empty() ? "" : ", ") + std::string(e.name);
    return Malformed("is required (one of " + names + ")", o.PathOf("kind"));
  }
  SurfaceKind kind = SurfaceKind::kBezier;
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<SurfaceKind>("kind", kSurfaceKinds, &kind));
  SurfaceSpec spec = EmptySpec(kind);
  SURFDEFORM_RETURN_IF_ERROR(std::visit([&o](auto& s) { return ReadFields(o, s); }, spec));
  if (const auto* m = std::get_if<MeshSpec>(&spec);
      m != nullptr && !IsSurfaceIdShaped(m->model_id)) {
    return InvalidArgument(
        "must be the id of an uploaded mesh, returned by POST /v1/models (32 hex digits)",
        o.PathOf("model_id"));
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return spec;
}

json SurfaceJson(const SurfaceSpec& spec) {
  json j = {{"kind", KindName(KindOf(spec))}};
  std::visit([&j](const auto& s) { WriteFields(s, &j); }, spec);
  return j;
}

Status ReadSampling(JsonObject& parent, SamplingOptions* out) {
  const json* v = parent.Find("sampling");
  if (v == nullptr) return Status::Ok();
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(*v, parent.PathOf("sampling")));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("nu", &out->nu));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("nv", &out->nv));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return ValidateSampling(*out).WithFieldPrefix(parent.PathOf("sampling"));
}

Status ReadFlatten(JsonObject& parent, FlattenSettings* out) {
  const json* v = parent.Find("flatten");
  if (v == nullptr) return Status::Ok();
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(*v, parent.PathOf("flatten")));
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<FlattenMethod>("method", kFlattenMethods, &out->method));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("range", &out->range));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("tolerance", &out->tolerance));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("max_iterations", &out->max_iterations));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("step", &out->step));
  SURFDEFORM_RETURN_IF_ERROR(o.Boolean("exact_developable", &out->exact_developable));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("lattice_factor", &out->lattice_factor));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("relax_steps", &out->relax_steps));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  // The engine's own rules name the field without the prefix.
  return ValidateFlattenSettings(*out).WithFieldPrefix(parent.PathOf("flatten"));
}

Status ReadSurfaceParts(JsonObject& o, SurfaceRequest* out) {
  const json* surface = o.Find("surface");
  if (surface == nullptr) return Malformed("is required", o.PathOf("surface"));
  SURFDEFORM_ASSIGN_OR_RETURN(auto spec, ReadSurface(*surface, o.PathOf("surface")));
  out->surface = std::move(spec);
  SURFDEFORM_RETURN_IF_ERROR(ReadSampling(o, &out->sampling));
  return ReadFlatten(o, &out->flatten);
}

Status ReadPlacement(JsonObject& parent, PlacementSettings* out) {
  const json* v = parent.Find("placement");
  if (v == nullptr) return ValidatePlacementSettings(*out);
  const std::string path = parent.PathOf("placement");
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(*v, path));
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<UpAxis>("up", kUpAxes, &out->up));
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<RigidMode>("rigid", kRigidModes, &out->rigid));
  if (const json* a = o.Find("anchor"); a != nullptr) {
    if (a->is_number()) {
      out->anchor = AnchorMode::kValue;
      out->anchor_value = a->get<double>();
    } else {
      SURFDEFORM_RETURN_IF_ERROR(o.Choice<AnchorMode>("anchor", kAnchorModes, &out->anchor));
    }
  }
  if (const json* c = o.Find("center"); c != nullptr) {
    if (c->is_string()) {
      if (c->get_ref<const std::string&>() != "center") {
        return InvalidArgument(
            "must be \"center\", [x, y] in sheet units or {\"fraction\": [fx, fy]}",
            o.PathOf("center"));
      }
      out->center_mode = CenterMode::kSheetCenter;
    } else if (c->is_object()) {
      SURFDEFORM_ASSIGN_OR_RETURN(auto f, JsonObject::Open(*c, o.PathOf("center")));
      const json* fr = f.Find("fraction");
      if (fr == nullptr) return Malformed("is required", f.PathOf("fraction"));
      SURFDEFORM_RETURN_IF_ERROR(ReadVec2(*fr, f.PathOf("fraction"), &out->center));
      SURFDEFORM_RETURN_IF_ERROR(f.Finish());
      out->center_mode = CenterMode::kFraction;
    } else {
      SURFDEFORM_RETURN_IF_ERROR(ReadVec2(*c, o.PathOf("center"), &out->center));
      out->center_mode = CenterMode::kSheetUnits;
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Number("rotation_deg", &out->rotation_deg));
  if (const json* s = o.Find("scale"); s != nullptr) {
    if (s->is_string() && s->get_ref<const std::string&>() == "fit") {
      out->fit = true;
    } else if (s->is_number()) {
      out->fit = false;
      out->scale = s->get<double>();
    } else {
      return Malformed("must be a positive number or \"fit\", got " + JsonTypeName(*s),
                       o.PathOf("scale"));
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Number("fit_margin", &out->fit_margin));
  SURFDEFORM_RETURN_IF_ERROR(o.Choice<OutsideMode>("outside", kOutsideModes, &out->outside));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return ValidatePlacementSettings(*out);  // names "placement.*" itself
}

Status ReadOutput(JsonObject& parent, OutputOptions* out) {
  const json* v = parent.Find("output");
  if (v == nullptr) return Status::Ok();
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(*v, parent.PathOf("output")));
  if (o.Find("format") != nullptr) {
    OutputFormat format = OutputFormat::kDrc;
    SURFDEFORM_RETURN_IF_ERROR(o.Choice<OutputFormat>("format", kOutputFormats, &format));
    out->format = format;
  }
  if (const json* d = o.Find("draco"); d != nullptr) {
    out->draco_given = true;
    SURFDEFORM_ASSIGN_OR_RETURN(auto dj, JsonObject::Open(*d, o.PathOf("draco")));
    SURFDEFORM_RETURN_IF_ERROR(dj.Integer("position_bits", &out->draco.position_bits));
    SURFDEFORM_RETURN_IF_ERROR(dj.Integer("normal_bits", &out->draco.normal_bits));
    SURFDEFORM_RETURN_IF_ERROR(dj.Integer("uv_bits", &out->draco.uv_bits));
    SURFDEFORM_RETURN_IF_ERROR(dj.Integer("color_bits", &out->draco.color_bits));
    SURFDEFORM_RETURN_IF_ERROR(dj.Integer("speed", &out->draco.speed));
    SURFDEFORM_RETURN_IF_ERROR(dj.Boolean("sequential", &out->draco.sequential));
    SURFDEFORM_RETURN_IF_ERROR(dj.Finish());
    SURFDEFORM_RETURN_IF_ERROR(ValidateDracoOptions(out->draco));  // names output.draco.*
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Boolean("distortion", &out->distortion));
  if (o.Find("compression") != nullptr) {
    GlbCompression c = GlbCompression::kDraco;
    SURFDEFORM_RETURN_IF_ERROR(o.Choice<GlbCompression>("compression", kGlbCompressions, &c));
    out->compression = c;
  }
  return o.Finish();
}

Status ReadSubdivision(JsonObject& parent, SubdivisionSettings* out) {
  const json* v = parent.Find("subdivision");
  if (v == nullptr) return Status::Ok();
  SURFDEFORM_ASSIGN_OR_RETURN(auto s, JsonObject::Open(*v, parent.PathOf("subdivision")));
  SURFDEFORM_RETURN_IF_ERROR(s.Choice<SubdivisionMode>("mode", kSubdivisionModes, &out->mode));
  SURFDEFORM_RETURN_IF_ERROR(s.Number("epsilon", &out->epsilon));
  SURFDEFORM_RETURN_IF_ERROR(s.Number("tolerance", &out->tolerance));
  SURFDEFORM_RETURN_IF_ERROR(s.Finish());
  return ValidateSubdivisionSettings(*out);
}

// "animation" (keyframes, interpolation, frames, fps) and, beside it,
// "sampling" and "flatten".
Status ReadAnimationParts(JsonObject& parent, AnimationRequest* out) {
  const json* v = parent.Find("animation");
  if (v == nullptr) return Malformed("is required", parent.PathOf("animation"));
  const std::string path = parent.PathOf("animation");
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(*v, path));
  AnimationSpec& spec = out->animation;
  const json* keys = o.Find("keyframes");
  if (keys == nullptr) return Malformed("is required", o.PathOf("keyframes"));
  if (!keys->is_array()) {
    return Malformed("must be an array of {\"time\", \"surface\"}, got " + JsonTypeName(*keys),
                     o.PathOf("keyframes"));
  }
  for (size_t k = 0; k < keys->size(); ++k) {
    const std::string key_path = JoinPath(o.PathOf("keyframes"), k);
    SURFDEFORM_ASSIGN_OR_RETURN(JsonObject kj, JsonObject::Open((*keys)[k], key_path));
    Keyframe key;
    if (kj.Find("time") == nullptr) return Malformed("is required", kj.PathOf("time"));
    SURFDEFORM_RETURN_IF_ERROR(kj.Number("time", &key.time));
    const json* surface = kj.Find("surface");
    if (surface == nullptr) return Malformed("is required", kj.PathOf("surface"));
    SURFDEFORM_ASSIGN_OR_RETURN(key.surface, ReadSurface(*surface, kj.PathOf("surface")));
    SURFDEFORM_RETURN_IF_ERROR(kj.Finish());
    spec.keyframes.push_back(std::move(key));
  }
  SURFDEFORM_RETURN_IF_ERROR(
      o.Choice<Interpolation>("interpolation", kInterpolations, &spec.interpolation));
  SURFDEFORM_RETURN_IF_ERROR(o.Integer("frames", &spec.frames));
  SURFDEFORM_RETURN_IF_ERROR(o.Number("fps", &spec.fps));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  // The frame count against the server's own limit (published at /v1/info)
  // is the service's to check: here, only what makes an animation at all.
  SURFDEFORM_RETURN_IF_ERROR(
      ValidateAnimation(spec, std::numeric_limits<int>::max()).WithFieldPrefix(path));
  SURFDEFORM_RETURN_IF_ERROR(ReadSampling(parent, &out->sampling));
  return ReadFlatten(parent, &out->flatten);
}

// An optional id field ("surface_id", "model_id", "warm_start"): when
// present, a string of an id's shape, or an error naming the field and the
// route (`minted_by`) whose ids it takes.
Status ReadId(JsonObject& o, const char* key, const char* minted_by, std::string* out) {
  const json* v = o.Find(key);
  if (v == nullptr) return Status::Ok();
  if (!v->is_string()) return Malformed("must be a string, got " + JsonTypeName(*v), o.PathOf(key));
  *out = v->get<std::string>();
  if (!IsSurfaceIdShaped(*out)) {
    return InvalidArgument(
        std::string("must be an id returned by POST ") + minted_by + " (32 hex digits)",
        o.PathOf(key));
  }
  return Status::Ok();
}

// output.compression on POST /v1/deform: a GLB's (the format when none is
// given); output.draco only with Draco.
Status CheckGlbCompression(OutputOptions* out) {
  if (!out->compression) return Status::Ok();
  if (!out->format) out->format = OutputFormat::kGlb;
  if (*out->format != OutputFormat::kGlb) {
    return InvalidArgument(
        std::string("compresses a GLB (output.format \"glb\"); the format is \"") +
            OutputFormatName(*out->format) + "\"",
        "output.compression");
  }
  if (out->draco_given && *out->compression != GlbCompression::kDraco) {
    return InvalidArgument(
        std::string("output.draco sets Draco's encoder, and output.compression is \"") +
            std::string(NameOf<GlbCompression>(kGlbCompressions, *out->compression)) +
            "\": leave one out",
        "output.draco");
  }
  return Status::Ok();
}

}  // namespace

const char* OutputFormatName(OutputFormat format) {
  const std::string_view name = NameOf<OutputFormat>(kOutputFormats, format);
  return name.empty() ? "drc" : name.data();  // the table's literals end in NUL
}

const char* OutputMediaType(OutputFormat format) {
  switch (format) {
    case OutputFormat::kDrc:
      return "application/octet-stream";
    case OutputFormat::kGlb:
    case OutputFormat::kGlbPlain:
      return "model/gltf-binary";
    case OutputFormat::kObj:
      return "model/obj";
    case OutputFormat::kPly:
      return "application/x-ply";
    case OutputFormat::kStl:
      return "model/stl";
    case OutputFormat::k3mf:
      return "model/3mf";
  }
  return "application/octet-stream";
}

Result<SurfaceRequest> ParseSurfaceRequest(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(body, ""));
  SurfaceRequest request;
  SURFDEFORM_RETURN_IF_ERROR(ReadSurfaceParts(o, &request));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return request;
}

Result<CreateSurfaceRequest> ParseCreateSurfaceRequest(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(body, ""));
  CreateSurfaceRequest out;
  SURFDEFORM_RETURN_IF_ERROR(ReadId(o, "warm_start", "/v1/surfaces", &out.warm_start));
  SURFDEFORM_RETURN_IF_ERROR(ReadSurfaceParts(o, &out.request));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return out;
}

Result<PartRequest> ParsePartRequest(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(auto o, JsonObject::Open(body, ""));
  PartRequest out;
  const json* b = o.Find("body");
  if (b == nullptr) {
    return Malformed("is required: {\"thickness_mm\", \"side\"} or {\"model_id\"}", "body");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(auto bj, JsonObject::Open(*b, o.PathOf("body")));
  SURFDEFORM_RETURN_IF_ERROR(ReadId(bj, "model_id", "/v1/models", &out.body_model_id));
  const json* surface = o.Find("surface");
  SURFDEFORM_RETURN_IF_ERROR(ReadId(o, "surface_id", "/v1/surfaces", &out.surface_id));
  if (!out.body_model_id.empty()) {
    // An uploaded body is used as it is.
    for (const char* key : {"thickness_mm", "side"}) {
      if (bj.Find(key) != nullptr) {
        return Malformed("belongs to a body grown from a surface; body.model_id is a body as it is",
                         bj.PathOf(key));
      }
    }
    if (surface != nullptr || !out.surface_id.empty()) {
      return Malformed("an uploaded body (body.model_id) is used as it is: give no surface with it",
                       surface != nullptr ? "surface" : "surface_id");
    }
    if (o.Find("sampling") != nullptr) {
      return Malformed("samples a surface; an uploaded body (body.model_id) has its own triangles",
                       "sampling");
    }
  } else {
    if ((surface != nullptr) == !out.surface_id.empty()) {
      return Malformed(
          "give exactly one of \"surface\" (inline) or \"surface_id\" (from POST /v1/surfaces), "
          "or an uploaded body (body.model_id)",
          surface != nullptr ? "surface_id" : "surface");
    }
    if (surface != nullptr) {
      SURFDEFORM_ASSIGN_OR_RETURN(auto spec, ReadSurface(*surface, o.PathOf("surface")));
      out.surface = std::move(spec);
    }
    if (o.Find("sampling") != nullptr) {
      out.sampling.emplace();
      SURFDEFORM_RETURN_IF_ERROR(ReadSampling(o, &*out.sampling));
    }
    if (bj.Find("thickness_mm") == nullptr) {
      return Malformed("is required (or body.model_id: an uploaded body)",
                       bj.PathOf("thickness_mm"));
    }
    SURFDEFORM_RETURN_IF_ERROR(bj.Number("thickness_mm", &out.part.thickness_mm));
    SURFDEFORM_RETURN_IF_ERROR(bj.Choice<BodySide>("side", kBodySides, &out.part.side));
    const double t = out.part.thickness_mm;
    if (!(t > 0) || t > kMaxBodyThicknessMm) {
      return Status(ErrorCode::kInvalidArgument,
                    "must be more than 0 and at most " + Format("%g", kMaxBodyThicknessMm) +
                        " mm, got " + Format("%g", t),
                    "body.thickness_mm")
          .WithLimit(kMaxBodyThicknessMm, t);
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(bj.Finish());
  if (const json* p = o.Find("printer"); p != nullptr) {
    SURFDEFORM_ASSIGN_OR_RETURN(auto pj, JsonObject::Open(*p, o.PathOf("printer")));
    SURFDEFORM_RETURN_IF_ERROR(pj.Number("min_wall_mm", &out.part.min_wall_mm));
    SURFDEFORM_RETURN_IF_ERROR(pj.Number("min_detail_mm", &out.part.min_detail_mm));
    SURFDEFORM_RETURN_IF_ERROR(pj.Finish());
    for (const auto& [key, value] : {std::pair{"min_wall_mm", out.part.min_wall_mm},
                                     std::pair{"min_detail_mm", out.part.min_detail_mm}}) {
      if (!(value >= 0) || value > kMaxBodyThicknessMm) {
        return InvalidArgument("must be 0 (not checked) to " + Format("%g", kMaxBodyThicknessMm) +
                                   " mm, got " + Format("%g", value),
                               std::string("printer.") + key);
      }
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Boolean("strict", &out.part.strict));
  SURFDEFORM_RETURN_IF_ERROR(ReadOutput(o, &out.output));
  if (out.output.distortion) {
    return InvalidArgument("belongs to a deformation; a part has no map to measure",
                           "output.distortion");
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return out;
}

// The model's source besides model_id and the body: a text. Sets the
// placement's defaults for text (up +z, anchor bottom) before the
// placement is read.
Status ReadTextModel(JsonObject& o, std::optional<TextSettings>* text, const std::string& model_id,
                     PlacementSettings* placement) {
  SURFDEFORM_RETURN_IF_ERROR(ReadText(o, text));
  if (!text->has_value()) return Status::Ok();
  if (!model_id.empty()) {
    return Malformed("give one model: \"text\" or \"model_id\", not both", "model_id");
  }
  placement->up = UpAxis::kPosZ;
  placement->anchor = AnchorMode::kBottom;
  return Status::Ok();
}

Result<DeformParams> ParseDeformParams(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(body, ""));
  DeformParams params;
  SURFDEFORM_RETURN_IF_ERROR(ReadId(o, "model_id", "/v1/models", &params.model_id));
  const bool inline_surface = o.Find("surface") != nullptr;
  const json* id = o.Find("surface_id");
  const bool animated = o.Find("animation") != nullptr;
  if (static_cast<int>(inline_surface) + static_cast<int>(id != nullptr) +
          static_cast<int>(animated) !=
      1) {
    return Malformed(
        "give exactly one of \"surface\" (inline), \"surface_id\" (from POST "
        "/v1/surfaces) and \"animation\" (with \"frame\")",
        inline_surface ? (id != nullptr ? "surface_id" : "animation") : "surface");
  }
  const json* frame = o.Find("frame");
  if (animated) {
    AnimationRequest request;
    SURFDEFORM_RETURN_IF_ERROR(ReadAnimationParts(o, &request));
    if (frame == nullptr) {
      return Malformed("is required with \"animation\": the frame to deform, from 0", "frame");
    }
    SURFDEFORM_RETURN_IF_ERROR(o.Integer("frame", &params.frame));
    if (params.frame < 0 || params.frame >= request.animation.frames) {
      return InvalidArgument("must be from 0 to " + std::to_string(request.animation.frames - 1) +
                                 " (the animation's frames), got " + std::to_string(params.frame),
                             "frame");
    }
    params.animation = std::move(request);
  } else if (frame != nullptr) {
    return Malformed("belongs to an \"animation\"; a surface has no frames", "frame");
  } else if (inline_surface) {
    SurfaceRequest request;
    SURFDEFORM_RETURN_IF_ERROR(ReadSurfaceParts(o, &request));
    params.surface = std::move(request);
    SURFDEFORM_RETURN_IF_ERROR(ReadId(o, "warm_start", "/v1/surfaces", &params.warm_start));
  } else {
    SURFDEFORM_RETURN_IF_ERROR(ReadId(o, "surface_id", "/v1/surfaces", &params.surface_id));
    if (o.Find("sampling") != nullptr || o.Find("flatten") != nullptr) {
      return Malformed(
          "sampling and flatten belong to the surface named by surface_id; leave "
          "them out",
          o.Find("sampling") != nullptr ? "sampling" : "flatten");
    }
  }
  if (!params.surface && o.Find("warm_start") != nullptr) {
    return Malformed(
        "goes with an inline \"surface\": an edit of the surface it names, flattened "
        "here from that surface's sheet",
        "warm_start");
  }
  params.placement.up = UpAxis::kAuto;  // the API's default
  SURFDEFORM_RETURN_IF_ERROR(ReadTextModel(o, &params.text, params.model_id, &params.placement));
  SURFDEFORM_RETURN_IF_ERROR(ReadPlacement(o, &params.placement));
  SURFDEFORM_RETURN_IF_ERROR(ReadSubdivision(o, &params.subdivision));
  SURFDEFORM_RETURN_IF_ERROR(ReadOutput(o, &params.output));
  SURFDEFORM_RETURN_IF_ERROR(CheckGlbCompression(&params.output));
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return params;
}

Result<AnimateParams> ParseAnimateParams(const json& body) {
  SURFDEFORM_ASSIGN_OR_RETURN(JsonObject o, JsonObject::Open(body, ""));
  AnimateParams params;
  SURFDEFORM_RETURN_IF_ERROR(ReadId(o, "model_id", "/v1/models", &params.model_id));
  for (const char* other : {"surface", "surface_id", "frame"}) {
    if (o.Find(other) != nullptr) {
      return Malformed(std::string("does not belong to an animation: give \"animation\" with "
                                   "its keyframes (POST /v1/deform takes \"") +
                           other + "\")",
                       other);
    }
  }
  SURFDEFORM_RETURN_IF_ERROR(ReadAnimationParts(o, &params.animation));
  params.placement.up = UpAxis::kAuto;  // the API's default
  SURFDEFORM_RETURN_IF_ERROR(ReadTextModel(o, &params.text, params.model_id, &params.placement));
  SURFDEFORM_RETURN_IF_ERROR(ReadPlacement(o, &params.placement));
  SURFDEFORM_RETURN_IF_ERROR(ReadSubdivision(o, &params.subdivision));
  SURFDEFORM_RETURN_IF_ERROR(ReadOutput(o, &params.output));
  const OutputOptions& out = params.output;
  if (out.format && *out.format != OutputFormat::kGlb) {
    return InvalidArgument(std::string("an animation is a GLB of morph targets; got \"") +
                               OutputFormatName(*out.format) + "\"",
                           "output.format");
  }
  if (out.compression == GlbCompression::kDraco) {
    return InvalidArgument(
        "an animation's morph targets are written with meshopt or none (Draco compresses no "
        "morph targets)",
        "output.compression");
  }
  if (out.distortion) {
    return InvalidArgument(
        "the distortion map is not written into animations; ask POST "
        "/v1/deform for a frame with it",
        "output.distortion");
  }
  SURFDEFORM_RETURN_IF_ERROR(o.Finish());
  return params;
}

json CanonicalJson(const SurfaceRequest& r) {
  const FlattenSettings& f = r.flatten;
  return {{"surface", SurfaceJson(r.surface)},
          {"sampling", {{"nu", r.sampling.nu}, {"nv", r.sampling.nv}}},
          {"flatten",
           {{"method", FlattenMethodName(f.method)},
            {"range", f.range},
            {"tolerance", f.tolerance},
            {"max_iterations", f.max_iterations},
            {"step", f.step},
            {"exact_developable", f.exact_developable},
            {"lattice_factor", f.lattice_factor},
            {"relax_steps", f.relax_steps}}}};
}

json CanonicalJson(const AnimationRequest& r) {
  // The flattening and sampling as for one surface; the keyframes in order.
  SurfaceRequest first{r.animation.keyframes.front().surface, r.sampling, r.flatten};
  json j = CanonicalJson(first);
  j.erase("surface");
  json keys = json::array();
  for (const Keyframe& k : r.animation.keyframes) {
    keys.push_back({{"time", k.time}, {"surface", SurfaceJson(k.surface)}});
  }
  j["animation"] = {{"keyframes", std::move(keys)},
                    {"interpolation", std::string(NameOf<Interpolation>(
                                          kInterpolations, r.animation.interpolation))},
                    {"frames", r.animation.frames},
                    {"fps", r.animation.fps}};
  return j;
}

json CanonicalJson(const PlacementSettings& p) {
  json anchor = p.anchor == AnchorMode::kValue ? json(p.anchor_value)
                                               : json(EnumName(kAnchorModes, p.anchor));
  json center;
  switch (p.center_mode) {
    case CenterMode::kSheetCenter:
      center = "center";
      break;
    case CenterMode::kSheetUnits:
      center = {p.center.x(), p.center.y()};
      break;
    case CenterMode::kFraction:
      center = {{"fraction", {p.center.x(), p.center.y()}}};
      break;
  }
  json j = {{"up", EnumName(kUpAxes, p.up)},  {"rigid", EnumName(kRigidModes, p.rigid)},
            {"anchor", std::move(anchor)},    {"center", std::move(center)},
            {"rotation_deg", p.rotation_deg}, {"outside", EnumName(kOutsideModes, p.outside)}};
  if (p.fit) {
    j["scale"] = "fit";
    j["fit_margin"] = p.fit_margin;
  } else {
    j["scale"] = p.scale;
  }
  return j;
}

json CanonicalJson(const SubdivisionSettings& s) {
  return {{"mode", EnumName(kSubdivisionModes, s.mode)},
          {"epsilon", s.epsilon},
          {"tolerance", s.tolerance}};
}

json CanonicalJson(const DracoOptions& d) {
  return {{"position_bits", d.position_bits},
          {"normal_bits", d.normal_bits},
          {"uv_bits", d.uv_bits},
          {"color_bits", d.color_bits},
          {"speed", d.speed},
          {"sequential", d.sequential}};
}

namespace {

json OutputJson(const OutputOptions& o) {
  json j = {{"distortion", o.distortion}};
  if (o.format) j["format"] = OutputFormatName(*o.format);
  if (o.compression) {
    j["compression"] = EnumName(kGlbCompressions, *o.compression);
  }
  if (o.draco_given) j["draco"] = CanonicalJson(o.draco);
  return j;
}

// What a deformation and an animation share: the model, and what is done
// with it.
template <typename Params>
void WriteMeshParts(const Params& p, json* j) {
  if (!p.model_id.empty()) (*j)["model_id"] = p.model_id;
  if (p.text) (*j)["text"] = CanonicalJson(*p.text);
  (*j)["placement"] = CanonicalJson(p.placement);
  (*j)["subdivision"] = CanonicalJson(p.subdivision);
  (*j)["output"] = OutputJson(p.output);
}

}  // namespace

json ToJson(const CreateSurfaceRequest& r) {
  json j = CanonicalJson(r.request);
  if (!r.warm_start.empty()) j["warm_start"] = r.warm_start;
  return j;
}

json ToJson(const DeformParams& p) {
  json j = json::object();
  if (p.surface) {
    j = CanonicalJson(*p.surface);
    if (!p.warm_start.empty()) j["warm_start"] = p.warm_start;
  } else if (p.animation) {
    j = CanonicalJson(*p.animation);
    j["frame"] = p.frame;
  } else {
    j["surface_id"] = p.surface_id;
  }
  WriteMeshParts(p, &j);
  return j;
}

json ToJson(const AnimateParams& p) {
  json j = CanonicalJson(p.animation);
  WriteMeshParts(p, &j);
  return j;
}

std::string AnimationId(const AnimationRequest& request) {
  const std::string text = "surfdeform-animation-1\n" + CanonicalJson(request).dump();
  return Sha256Hex(text, 32);
}

std::string SurfaceId(const SurfaceRequest& request) {
  // The prefix versions the flattening: a change to the algorithm that
  // changes sheets must change it, so that old ids are not served new sheets.
  const std::string text = "surfdeform-sheet-1\n" + CanonicalJson(request).dump();
  return Sha256Hex(text, 32);
}

std::string ModelId(std::string_view mesh_bytes) { return Sha256Hex(mesh_bytes, 32); }

bool IsSurfaceIdShaped(std::string_view text) {
  if (text.size() != 32) return false;
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

}  // namespace surfdeform::proto
