#include "proto/wire.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "engine/local_origin.h"
#include "engine/option_table.h"

namespace femsimp::wire {

const char* BackendName(Backend b) { return b == Backend::kCell ? "cell" : "native"; }

namespace {

using google::protobuf::EnumValueDescriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

// The message that holds an option's field (EngineOptions, or its CellOptions `group`), and the
// field, found by the table's name. Fails only if the proto and the table disagree, which
// tests/service/option_table_test.cc rules out.
const FieldDescriptor* FieldOf(const OptionSpec& spec, const Message& m) {
  return m.GetDescriptor()->FindFieldByName(spec.name);
}

// Proto enum values are the table's choice names upper-cased after the enum's prefix
// (COST_KIND_QUADRIC); value 0 is the enum's UNSPECIFIED.
std::string EnumPrefix(const FieldDescriptor* f) {
  std::string unspecified = f->enum_type()->value(0)->name();
  return unspecified.substr(0, unspecified.size() - std::string("UNSPECIFIED").size());
}

absl::StatusOr<double> ChoiceOf(const OptionSpec& spec, const FieldDescriptor* f, int number) {
  const EnumValueDescriptor* v = f->enum_type()->FindValueByNumber(number);
  const std::string prefix = EnumPrefix(f);
  std::vector<std::string> known;
  for (size_t i = 0; i < spec.choices.size(); ++i) {
    known.push_back(absl::AsciiStrToUpper(absl::StrCat(prefix, spec.choices[i].name)));
    if (v != nullptr && v->name() == known.back()) return static_cast<double>(i);
  }
  return absl::InvalidArgumentError(absl::StrCat(spec.name, " = ", number,
                                                 " is not a known value: must be one of ",
                                                 absl::StrJoin(known, ", ")));
}

// The value of a field that was sent; nullopt when it was not (no presence: 0 means unset).
absl::StatusOr<std::optional<double>> ReadField(const OptionSpec& spec, const Message& m) {
  const FieldDescriptor* f = FieldOf(spec, m);
  const Reflection* r = m.GetReflection();
  if (f->has_presence() ? !r->HasField(m, f) : false) return std::nullopt;
  double v = 0;
  switch (f->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
      v = r->GetDouble(m, f);
      break;
    case FieldDescriptor::CPPTYPE_INT32:
      v = r->GetInt32(m, f);
      break;
    case FieldDescriptor::CPPTYPE_UINT64:
      v = static_cast<double>(r->GetUInt64(m, f));
      break;
    case FieldDescriptor::CPPTYPE_BOOL:
      v = r->GetBool(m, f) ? 1 : 0;
      break;
    case FieldDescriptor::CPPTYPE_ENUM: {
      const int number = r->GetEnumValue(m, f);
      if (number == 0) return std::nullopt;
      absl::StatusOr<double> choice = ChoiceOf(spec, f, number);
      if (!choice.ok()) return choice.status();
      return *choice;  // set (number != 0), even where the choice's index is 0
    }
    default:
      return absl::InternalError(absl::StrCat(spec.name, ": unexpected proto type"));
  }
  if (!f->has_presence() && v == 0) return std::nullopt;
  return v;
}

void WriteField(const OptionSpec& spec, double v, Message* m) {
  const FieldDescriptor* f = FieldOf(spec, *m);
  const Reflection* r = m->GetReflection();
  switch (f->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
      r->SetDouble(m, f, v);
      break;
    case FieldDescriptor::CPPTYPE_INT32:
      r->SetInt32(m, f, static_cast<int32_t>(v));
      break;
    case FieldDescriptor::CPPTYPE_UINT64:
      r->SetUInt64(m, f, static_cast<uint64_t>(v));
      break;
    case FieldDescriptor::CPPTYPE_BOOL:
      r->SetBool(m, f, v != 0);
      break;
    case FieldDescriptor::CPPTYPE_ENUM:
      r->SetEnum(m, f,
                 f->enum_type()->FindValueByName(absl::AsciiStrToUpper(
                     absl::StrCat(EnumPrefix(f), spec.choices[static_cast<size_t>(v)].name))));
      break;
    default:
      break;
  }
}

}  // namespace

void ToProto(const SimplifyOptions& o, bool threads_given, v1::EngineOptions* out) {
  for (const OptionSpec& spec : OptionTable()) {
    if (spec.cell_only() && o.backend != Backend::kCell) continue;
    Message* m = spec.cell_only() ? static_cast<Message*>(out->mutable_cell()) : out;
    double v = GetOption(spec, o);
    if (std::string_view(spec.name) == "threads" && !threads_given) v = 0;  // server default
    // Of a oneof (the target), only the member that is set.
    if (FieldOf(spec, *m)->real_containing_oneof() != nullptr && v == 0) continue;
    WriteField(spec, v, m);
  }
}

absl::StatusOr<SimplifyOptions> FromProto(const v1::EngineOptions& in, int default_threads,
                                          int max_threads) {
  SimplifyOptions o = PresetOptions(in.preset() == v1::PRESET_PAPER ? Preset::kPaper : Preset::kFe);
  o.threads = default_threads;  // threads 0 (unset): the server's default
  for (const OptionSpec& spec : OptionTable()) {
    // The cell options are read only for the cell back end (backend comes first in the table).
    if (spec.cell_only() && o.backend != Backend::kCell) continue;
    const Message& m = spec.cell_only() ? static_cast<const Message&>(in.cell()) : in;
    absl::StatusOr<std::optional<double>> v = ReadField(spec, m);
    if (!v.ok()) return v.status();
    if (*v) SetOption(spec, **v, &o);
  }
  // The documented range first (threads 1025 is out of it on any server), then the server's cap.
  if (absl::Status s = ValidateOptions(o); !s.ok()) return s;
  o.threads = std::min(o.threads, max_threads);
  return o;
}

void ToProto(const PassStats& p, v1::Progress* out) {
  out->set_pass(p.pass);
  out->set_vertices_left(p.vertices_left);
  out->set_removed(p.removed);
  out->set_tried(p.tried);
  out->set_candidates(p.candidates);
  out->set_lock_conflicts(p.lock_conflicts);
  out->set_inconsistent(p.inconsistent);
  out->set_rounds(p.rounds);
  out->set_seam_points_removed(p.seam_points_removed);
  out->set_placed(p.placed);
  out->set_placed_on_lines(p.placed_on_lines);
  out->set_boxes_kept(p.boxes_kept);
  for (int i = 0; i < static_cast<int>(Reject::kCount); ++i)
    (*out->mutable_rejections())[RejectName(static_cast<Reject>(i))] = p.rejections[i];
  out->set_seconds(p.seconds);
  out->set_busy_seconds(p.busy_seconds);
  if (p.cell) {
    const CellPassCounters& c = *p.cell;
    out->set_cache_hit_ratio(c.hit_ratio());
    v1::CellCounters* m = out->mutable_cell();
    m->set_cache_hits(c.cache_hits);
    m->set_cache_misses(c.cache_misses);
    m->set_stale_detected(c.stale_detected);
    m->set_stale_reread(c.stale_reread);
    m->set_stale_skipped(c.stale_skipped);
    m->set_dma_transfers(c.dma_transfers);
    m->set_dma_bytes(c.dma_bytes);
    m->set_atomic_ops(c.atomic_ops);
    m->set_thread_switches(c.thread_switches);
    m->set_busy_cycles(c.busy_cycles);
    m->set_modeled_cycles(c.modeled_cycles);
    out->set_ppe_cycles(p.ppe_cycles);
    out->set_spe_start_cycles(p.spe_start_cycles);
    out->set_modeled_pass_cycles(p.modeled_pass_cycles);
  }
}

PassStats FromProto(const v1::Progress& in) {
  PassStats p;
  p.pass = static_cast<int>(in.pass());
  p.vertices_left = in.vertices_left();
  p.removed = in.removed();
  p.tried = in.tried();
  p.candidates = in.candidates();
  p.lock_conflicts = in.lock_conflicts();
  p.inconsistent = in.inconsistent();
  p.rounds = in.rounds();
  p.seam_points_removed = in.seam_points_removed();
  p.placed = in.placed();
  p.placed_on_lines = in.placed_on_lines();
  p.boxes_kept = in.boxes_kept();
  for (int i = 0; i < static_cast<int>(Reject::kCount); ++i) {
    auto it = in.rejections().find(RejectName(static_cast<Reject>(i)));
    if (it != in.rejections().end()) p.rejections[i] = it->second;
  }
  p.seconds = in.seconds();
  p.busy_seconds = in.busy_seconds();
  if (in.has_cell()) {
    const v1::CellCounters& m = in.cell();
    CellPassCounters c;
    c.cache_hits = m.cache_hits();
    c.cache_misses = m.cache_misses();
    c.stale_detected = m.stale_detected();
    c.stale_reread = m.stale_reread();
    c.stale_skipped = m.stale_skipped();
    c.dma_transfers = m.dma_transfers();
    c.dma_bytes = m.dma_bytes();
    c.atomic_ops = m.atomic_ops();
    c.thread_switches = m.thread_switches();
    c.busy_cycles = m.busy_cycles();
    c.modeled_cycles = m.modeled_cycles();
    p.cell = c;
    p.ppe_cycles = in.ppe_cycles();
    p.spe_start_cycles = in.spe_start_cycles();
    p.modeled_pass_cycles = in.modeled_pass_cycles();
  }
  return p;
}

void RepairToProto(const RepairReport& r, v1::RepairReport* out) {
  for (size_t k = 0; k < kNumRepairKinds; ++k)
    if (IsRepairChange(static_cast<RepairKind>(k)) || r.counts[k] > 0)
      (*out->mutable_counts())[RepairKindName(static_cast<RepairKind>(k))] = r.counts[k];
  for (const RepairRecord& rec : r.records) {
    v1::RepairRecord* m = out->add_records();
    m->set_kind(RepairKindName(rec.kind));
    m->set_facet(rec.facet);
    m->set_vertex(rec.vertex);
    for (double x : rec.at) m->add_at(x);
    m->set_detail(rec.detail);
  }
  out->set_weld_tolerance(r.weld_tolerance_relative);
  out->set_weld_tolerance_abs(r.weld_tolerance_absolute);
  out->set_diagonal(r.diagonal);
}

RepairReport RepairFromProto(const v1::RepairReport& in) {
  RepairReport r;
  for (size_t k = 0; k < kNumRepairKinds; ++k) {
    const RepairKind kind = static_cast<RepairKind>(k);
    if (auto it = in.counts().find(RepairKindName(kind)); it != in.counts().end())
      r.counts[k] = it->second;
    for (const v1::RepairRecord& m : in.records()) {
      if (m.kind() != RepairKindName(kind)) continue;
      RepairRecord rec{
          .kind = kind, .facet = m.facet(), .vertex = m.vertex(), .detail = m.detail()};
      for (int i = 0; i < 3 && i < m.at_size(); ++i) rec.at[i] = m.at(i);
      r.records.push_back(std::move(rec));
    }
  }
  r.weld_tolerance_relative = in.weld_tolerance();
  r.weld_tolerance_absolute = in.weld_tolerance_abs();
  r.diagonal = in.diagonal();
  return r;
}

namespace {

void MassToProto(const MassSummary& m, v1::MassProperties* out) {
  out->set_solid(m.solid);
  out->set_measure(m.measure);
  out->set_area(m.area);
  for (double c : {m.centroid.x, m.centroid.y, m.centroid.z}) out->add_centroid(c);
  for (int i = 0; i < 3; ++i) {
    out->add_principal_moments(m.principal_moments[i]);
    const DVec3& a = m.principal_axes[i];
    for (double c : {a.x, a.y, a.z}) out->add_principal_axes(c);
  }
}

MassSummary MassFromProto(const v1::MassProperties& in) {
  MassSummary m;
  m.solid = in.solid();
  m.measure = in.measure();
  m.area = in.area();
  const auto at = [](const auto& values, int i) { return i < values.size() ? values[i] : 0.0; };
  m.centroid = {at(in.centroid(), 0), at(in.centroid(), 1), at(in.centroid(), 2)};
  for (int i = 0; i < 3; ++i) {
    m.principal_moments[i] = at(in.principal_moments(), i);
    if (in.principal_axes_size() == 9)
      m.principal_axes[i] = {in.principal_axes(3 * i), in.principal_axes(3 * i + 1),
                             in.principal_axes(3 * i + 2)};
  }
  return m;
}

}  // namespace

void FidelityToProto(const SimplifyResult& r, v1::Result* out) {
  out->set_feature_edges(r.feature_edges);
  out->set_corner_vertices(r.corner_vertices);
  out->set_tolerance_abs(r.tolerance_abs);
  out->set_deviation_bound(r.deviation_bound);
  out->set_volume_change(r.volume_change);
  out->set_centroid_shift(r.centroid_shift);
  out->set_max_field_change(r.max_field_change);
  MassToProto(r.input_mass, out->mutable_input_mass());
  MassToProto(r.output_mass, out->mutable_output_mass());
  out->set_inertia_change(r.inertia_change);
  out->set_wall_limited_share(r.wall_limited_share);
  out->set_thinnest_wall(r.thinnest_wall);
  v1::OutputCrossings* crossings = out->mutable_output_crossings();
  crossings->set_pairs(r.output_crossings.pairs);
  crossings->set_cut_short(r.output_crossings.cut_short);
  if (r.output_crossings.pairs > 0) {
    crossings->set_face_a(r.output_crossings.face_a);
    crossings->set_face_b(r.output_crossings.face_b);
    for (double x : r.output_crossings.at) crossings->add_at(x);
  }
  const SoupCrossings::Overlaps& overlaps = r.output_crossings.overlaps;
  v1::Overlaps* overlaps_out = crossings->mutable_overlaps();
  overlaps_out->set_pairs(overlaps.pairs);
  if (overlaps.pairs > 0) {
    overlaps_out->set_area(overlaps.area);
    overlaps_out->set_face_a(overlaps.face_a);
    overlaps_out->set_face_b(overlaps.face_b);
    for (double x : overlaps.at) overlaps_out->add_at(x);
  }
  const SoupCrossings::Folds& folds = r.output_crossings.folds;
  v1::Folds* folds_out = crossings->mutable_folds();
  folds_out->set_pairs(folds.pairs);
  if (folds.pairs > 0) {
    folds_out->set_face_a(folds.face_a);
    folds_out->set_face_b(folds.face_b);
    for (double x : folds.at) folds_out->add_at(x);
  }
  v1::CoordinatePrecision* coordinates = out->mutable_coordinates();
  coordinates->set_magnitude(r.coordinates.magnitude);
  coordinates->set_spacing(r.coordinates.spacing);
  coordinates->set_diagonal(r.coordinates.diagonal);
  for (const SimplifyResult::PartVolume& part : r.parts) {
    v1::PartVolume* p = out->add_parts();
    p->set_input_volume(part.input);
    p->set_output_volume(part.output);
  }
}

void FidelityFromProto(const v1::Result& in, SimplifyResult* out) {
  out->feature_edges = in.feature_edges();
  out->corner_vertices = in.corner_vertices();
  out->tolerance_abs = in.tolerance_abs();
  out->deviation_bound = in.deviation_bound();
  out->volume_change = in.volume_change();
  out->centroid_shift = in.centroid_shift();
  out->max_field_change = in.max_field_change();
  out->input_mass = MassFromProto(in.input_mass());
  out->output_mass = MassFromProto(in.output_mass());
  out->inertia_change = in.inertia_change();
  out->wall_limited_share = in.wall_limited_share();
  out->thinnest_wall = in.thinnest_wall();
  out->parts.clear();
  for (const v1::PartVolume& p : in.parts())
    out->parts.push_back({p.input_volume(), p.output_volume()});
  const v1::OutputCrossings& crossings = in.output_crossings();
  out->output_crossings.pairs = crossings.pairs();
  out->output_crossings.cut_short = crossings.cut_short();
  out->output_crossings.face_a = crossings.face_a();
  out->output_crossings.face_b = crossings.face_b();
  for (int i = 0; i < 3 && i < crossings.at_size(); ++i)
    out->output_crossings.at[i] = crossings.at(i);
  const v1::Overlaps& overlaps = crossings.overlaps();
  SoupCrossings::Overlaps& overlaps_out = out->output_crossings.overlaps;
  overlaps_out.pairs = overlaps.pairs();
  overlaps_out.area = overlaps.area();
  overlaps_out.face_a = overlaps.face_a();
  overlaps_out.face_b = overlaps.face_b();
  for (int i = 0; i < 3 && i < overlaps.at_size(); ++i) overlaps_out.at[i] = overlaps.at(i);
  const v1::Folds& folds = crossings.folds();
  SoupCrossings::Folds& folds_out = out->output_crossings.folds;
  folds_out.pairs = folds.pairs();
  folds_out.face_a = folds.face_a();
  folds_out.face_b = folds.face_b();
  for (int i = 0; i < 3 && i < folds.at_size(); ++i) folds_out.at[i] = folds.at(i);
  out->coordinates.magnitude = in.coordinates().magnitude();
  out->coordinates.spacing = in.coordinates().spacing();
  out->coordinates.diagonal = in.coordinates().diagonal();
}

absl::Status CheckFieldNames(const google::protobuf::RepeatedPtrField<std::string>& names,
                             const std::string& where) {
  if (static_cast<size_t>(names.size()) > kMaxFaceFields)
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": ", names.size(), " face fields, at most ", kMaxFaceFields));
  for (int i = 0; i < names.size(); ++i) {
    if (names[i].empty() || names[i].size() > kMaxFieldNameBytes)
      return absl::InvalidArgumentError(absl::StrCat(where, "[", i, "] is ", names[i].size(),
                                                     " bytes (1 to ", kMaxFieldNameBytes, ")"));
    for (int j = 0; j < i; ++j)
      if (names[j] == names[i])
        return absl::InvalidArgumentError(absl::StrCat(where, ": '", names[i], "' is given twice"));
  }
  return absl::OkStatus();
}

std::vector<std::string> FieldNames(const RawMesh& mesh) {
  std::vector<std::string> names;
  for (const FaceField& f : mesh.face_fields) names.push_back(f.name);
  return names;
}

size_t ChunkCount(const RawMesh& mesh, size_t chunk_vertices, size_t chunk_faces) {
  const size_t by_vertices = (mesh.num_vertices() + chunk_vertices - 1) / chunk_vertices;
  const size_t by_faces = (mesh.num_faces() + chunk_faces - 1) / chunk_faces;
  return std::max(by_vertices, by_faces);
}

void FillChunk(const RawMesh& mesh, size_t k, v1::MeshChunk* chunk, size_t chunk_vertices,
               size_t chunk_faces) {
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  const size_t v = k * chunk_vertices, f = k * chunk_faces;
  if (v < nv) {
    size_t end = std::min(nv, v + chunk_vertices);
    chunk->mutable_positions()->Add(mesh.positions.begin() + 3 * v,
                                    mesh.positions.begin() + 3 * end);
  }
  if (f < nf) {
    size_t end = std::min(nf, f + chunk_faces);
    chunk->mutable_indices()->Add(mesh.triangles.begin() + 3 * f, mesh.triangles.begin() + 3 * end);
    if (!mesh.face_groups.empty())
      chunk->mutable_face_groups()->Add(mesh.face_groups.begin() + f,
                                        mesh.face_groups.begin() + end);
    for (const FaceField& field : mesh.face_fields)
      chunk->add_face_fields()->mutable_values()->Add(field.values.begin() + f,
                                                      field.values.begin() + end);
  }
}

size_t ForEachChunk(const RawMesh& mesh, const std::function<bool(v1::MeshChunk&)>& emit,
                    size_t chunk_vertices, size_t chunk_faces) {
  const size_t count = ChunkCount(mesh, chunk_vertices, chunk_faces);
  for (size_t k = 0; k < count; ++k) {
    v1::MeshChunk chunk;
    FillChunk(mesh, k, &chunk, chunk_vertices, chunk_faces);
    if (!emit(chunk)) return k + 1;
  }
  return count;
}

absl::StatusOr<std::array<double, 3>> OriginFromProto(
    const google::protobuf::RepeatedField<double>& origin, const std::string& where) {
  std::array<double, 3> out{};
  if (origin.empty()) return out;
  if (origin.size() != 3)
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": ", origin.size(), " coordinates (expected none or x, y, z)"));
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(origin[k]))
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": coordinate ", k, " is not finite (", origin[k], ")"));
    out[k] = origin[k];
  }
  return out;
}

void OriginToProto(const std::array<double, 3>& origin,
                   google::protobuf::RepeatedField<double>* out) {
  out->Clear();
  if (AtOrigin(origin)) return;
  out->Add(origin.begin(), origin.end());
}

MeshAssembler::MeshAssembler(uint64_t vertices, uint64_t faces, bool face_groups,
                             std::vector<std::string> field_names,
                             const std::array<double, 3>& origin)
    : vertices_(vertices), faces_(faces), face_groups_(face_groups) {
  mesh_.origin = origin;
  // Reserve is bounded by the caller's limits, checked before construction.
  mesh_.positions.reserve(3 * vertices);
  mesh_.triangles.reserve(3 * faces);
  if (face_groups) mesh_.face_groups.reserve(faces);
  for (std::string& name : field_names) {
    mesh_.face_fields.push_back({std::move(name), {}});
    mesh_.face_fields.back().values.reserve(faces);
  }
}

absl::Status MeshAssembler::Add(const v1::MeshChunk& chunk) {
  ++chunks_;
  const auto& pos = chunk.positions();
  const auto& idx = chunk.indices();
  const auto& grp = chunk.face_groups();
  if (pos.size() % 3 != 0)
    return absl::InvalidArgumentError(
        absl::StrCat("chunk ", chunks_, ": ", pos.size(), " coordinates is not a multiple of 3"));
  if (idx.size() % 3 != 0)
    return absl::InvalidArgumentError(
        absl::StrCat("chunk ", chunks_, ": ", idx.size(), " indices is not a multiple of 3"));
  const uint64_t have_v = mesh_.positions.size() / 3, have_f = mesh_.triangles.size() / 3;
  if (have_v + pos.size() / 3 > vertices_)
    return absl::InvalidArgumentError(
        absl::StrCat("chunk ", chunks_, ": vertices past the declared vertex_count ", vertices_,
                     " (", have_v + pos.size() / 3, " received)"));
  if (have_f + idx.size() / 3 > faces_)
    return absl::InvalidArgumentError(absl::StrCat("chunk ", chunks_,
                                                   ": faces past the declared face_count ", faces_,
                                                   " (", have_f + idx.size() / 3, " received)"));
  if (!face_groups_ && !grp.empty())
    return absl::InvalidArgumentError(absl::StrCat(
        "chunk ", chunks_, ": face_groups sent but the spec did not declare has_face_groups"));
  if (face_groups_ && mesh_.face_groups.size() + grp.size() > faces_)
    return absl::InvalidArgumentError(
        absl::StrCat("chunk ", chunks_, ": face groups past the declared face_count ", faces_));
  const auto& fields = chunk.face_fields();
  if (!fields.empty() && static_cast<size_t>(fields.size()) != mesh_.face_fields.size())
    return absl::InvalidArgumentError(absl::StrCat(
        "chunk ", chunks_, ": ", fields.size(), " face field arrays but the spec declares ",
        mesh_.face_fields.size(), " face fields (",
        absl::StrJoin(mesh_.face_fields, ", ",
                      [](std::string* out, const FaceField& f) { out->append(f.name); }),
        ")"));
  for (int k = 0; k < fields.size(); ++k) {
    const FaceField& field = mesh_.face_fields[k];
    const auto& values = fields[k].values();
    if (field.values.size() + values.size() > faces_)
      return absl::InvalidArgumentError(absl::StrCat("chunk ", chunks_, ": values of face field '",
                                                     field.name, "' past the declared face_count ",
                                                     faces_));
    for (int i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        return absl::InvalidArgumentError(
            absl::StrCat("chunk ", chunks_, ": face field '", field.name, "': face ",
                         field.values.size() + i, " has a non-finite value (", values[i], ")"));
  }
  for (int i = 0; i < pos.size(); ++i)
    if (!std::isfinite(pos[i]))
      return absl::InvalidArgumentError(absl::StrCat("chunk ", chunks_, ": vertex ", have_v + i / 3,
                                                     " has a non-finite coordinate (", pos[i],
                                                     ")"));
  for (int i = 0; i < idx.size(); ++i)
    if (idx[i] >= vertices_)
      return absl::InvalidArgumentError(absl::StrCat("chunk ", chunks_, ": face ", have_f + i / 3,
                                                     " references vertex ", idx[i],
                                                     " but vertex_count is ", vertices_));
  mesh_.positions.insert(mesh_.positions.end(), pos.begin(), pos.end());
  mesh_.triangles.insert(mesh_.triangles.end(), idx.begin(), idx.end());
  mesh_.face_groups.insert(mesh_.face_groups.end(), grp.begin(), grp.end());
  for (int k = 0; k < fields.size(); ++k)
    mesh_.face_fields[k].values.insert(mesh_.face_fields[k].values.end(),
                                       fields[k].values().begin(), fields[k].values().end());
  return absl::OkStatus();
}

absl::StatusOr<RawMesh> MeshAssembler::Finish() {
  const uint64_t have_v = mesh_.num_vertices(), have_f = mesh_.num_faces();
  if (have_v != vertices_ || have_f != faces_)
    return absl::InvalidArgumentError(absl::StrCat("stream ended early: received ", have_v, " of ",
                                                   vertices_, " vertices and ", have_f, " of ",
                                                   faces_, " faces in ", chunks_, " chunks"));
  if (face_groups_ && mesh_.face_groups.size() != faces_)
    return absl::InvalidArgumentError(absl::StrCat(
        "stream ended early: received ", mesh_.face_groups.size(), " of ", faces_, " face groups"));
  for (const FaceField& field : mesh_.face_fields)
    if (field.values.size() != faces_)
      return absl::InvalidArgumentError(absl::StrCat("stream ended early: received ",
                                                     field.values.size(), " of ", faces_,
                                                     " values of face field '", field.name, "'"));
  return std::move(mesh_);
}

}  // namespace femsimp::wire
