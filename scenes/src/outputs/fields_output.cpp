// DIR/fields/frame_NNNNNN.vti + .npy and DIR/fields.pvd (output.fields): every frame's
// binned fields (seed 003 §4.1, as the run hands them over in its Snapshot, before any
// drawing filter) as VTK XML ImageData with cell data on the bins, a ParaView collection
// with each frame's simulated time, and the same arrays as one NumPy structured array a
// frame. Each file is written whole through io::AtomicFile; fields.pvd is rewritten after
// every frame so that it always lists exactly the frames on disk.
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/core/binning.hpp"
#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/atomic_file.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

static_assert(std::endian::native == std::endian::little, "the field files are written little-endian");

constexpr Key<bool> fields{"output.fields"};
constexpr std::string_view kVtiFiles = "fields/frame_*.vti";
constexpr std::string_view kNpyFiles = "fields/frame_*.npy";

// One array of the files: per bin, `components` values of one type.
struct Array {
  enum Type { f64, u64, u8 };
  Array(Type t, std::string n, int c = 1) : type(t), name(std::move(n)), components(c) {}
  Type type;
  std::string name;
  int components;
  std::vector<double> f;
  std::vector<std::uint64_t> u;
  std::vector<std::uint8_t> m;

  std::size_t bytes() const { return type == f64 ? f.size() * 8 : type == u64 ? u.size() * 8 : m.size(); }
  const char* data() const {
    return type == f64 ? reinterpret_cast<const char*>(f.data())
                       : type == u64 ? reinterpret_cast<const char*>(u.data()) : reinterpret_cast<const char*>(m.data());
  }
  std::string_view vtk_type() const { return type == f64 ? "Float64" : type == u64 ? "UInt64" : "UInt8"; }
  std::string_view npy_type() const { return type == f64 ? "<f8" : type == u64 ? "<u8" : "|u1"; }
  std::size_t item() const { return type == u8 ? 1 : 8; }
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Array scalar(std::string name, const core::ScalarField& field) {
  Array a{Array::f64, std::move(name)};
  a.f.resize(field.values.size());
  for (std::size_t b = 0; b < a.f.size(); ++b) a.f[b] = field.mask[b] ? field.values[b] : kNaN;
  return a;
}

// A frame's fields on its grid, placed in the box: the grid's axes u, v are box axes, and
// the averaged third axis w (DEM's slab; z = 0 for 2D) is one cell thick.
struct FrameFields {
  core::GridGeometry grid;
  std::array<int, 2> axes{0, 1};
  int normal = 2;
  std::array<double, 3> origin{}, spacing{};
  std::array<int, 3> cells{1, 1, 1};
  std::vector<Array> arrays;
};

FrameFields frame_fields(const render::Snapshot& s) {
  const render::NamedField* density = s.field("density");
  FrameFields out;
  out.grid = density->field.grid;
  const core::GridGeometry& g = out.grid;
  out.axes = s.exposure->axes;
  out.normal = 3 - out.axes[0] - out.axes[1];
  const int u = out.axes[0], v = out.axes[1], w = out.normal;
  out.origin[u] = g.lo.x();
  out.origin[v] = g.lo.y();
  out.spacing[u] = g.dx();
  out.spacing[v] = g.dy();
  out.cells[u] = g.nx;
  out.cells[v] = g.ny;
  // The averaged axis: one cell spanning the slab the bins average over (sample.slab, else
  // the box) in 3D;
  // in 2D one cell of unit depth from z = 0.
  const auto& slab = s.exposure->slab;
  const double across_lo = slab ? (*slab)[0] : s.lo[w], across_hi = slab ? (*slab)[1] : s.hi[w];
  const double depth = s.dim == 3 ? across_hi - across_lo : 0.0;
  out.origin[w] = s.dim == 3 ? across_lo : 0.0;
  out.spacing[w] = depth > 0 ? depth : 1.0;

  auto& a = out.arrays;
  a.push_back(scalar("number_density", density->field));
  if (const auto* f = s.field("fraction")) a.push_back(scalar(s.dim == 3 ? "solid_fraction" : "area_fraction", f->field));
  // 2D: kT (Eq. 4.9, i = 2) in the engine's energy units. 3D: the same definition with
  // i = 3 and masses in kg — m<|C|²>/3 in joules, a velocity variance, not a thermal kT.
  if (const auto* f = s.field("temperature")) a.push_back(scalar(s.dim == 3 ? "granular_temperature" : "kT", f->field));
  if (s.velocity) {
    const core::VectorField& vel = *s.velocity;
    Array mean{Array::f64, "mean_velocity", 3};
    Array norm{Array::f64, "speed_of_mean_velocity"};
    mean.f.assign(3 * g.size(), 0.0);
    norm.f.resize(g.size());
    for (std::size_t b = 0; b < g.size(); ++b) {
      const bool ok = vel.mask[b] != 0;
      mean.f[3 * b + u] = ok ? vel.values[b].x() : kNaN;
      mean.f[3 * b + v] = ok ? vel.values[b].y() : kNaN;
      mean.f[3 * b + w] = ok ? 0.0 : kNaN;  // the binning keeps the in-plane components only
      norm.f[b] = ok ? vel.values[b].norm() : kNaN;
    }
    a.push_back(std::move(mean));
    a.push_back(std::move(norm));
  }
  if (const auto* f = s.field("speed")) a.push_back(scalar("mean_speed", f->field));
  if (s.velocity) a.push_back(scalar("vorticity", core::vorticity(*s.velocity)));
  if (const auto* f = s.field("open_fraction")) a.push_back(scalar("open_fraction", f->field));
  if (const auto* f = s.field("samples")) {
    Array c{Array::u64, "sample_count"};
    for (double x : f->field.values) c.u.push_back(std::uint64_t(x));
    a.push_back(std::move(c));
  }
  Array mask{Array::u8, "mask"};
  mask.m = density->field.mask;  // 0: the bin lies in a solid (obstacle, beyond the outlet filter)
  a.push_back(std::move(mask));
  return out;
}

std::string vti(const FrameFields& f, const render::Snapshot& s) {
  std::string x;
  auto it = std::back_inserter(x);
  fmt::format_to(it, "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                     "header_type=\"UInt64\">\n");
  const std::string extent = fmt::format("0 {} 0 {} 0 {}", f.cells[0], f.cells[1], f.cells[2]);
  // The averaged axis is one cell thick (two points): ParaView then draws the bins as cells.
  fmt::format_to(it, "  <ImageData WholeExtent=\"{}\" Origin=\"{} {} {}\" Spacing=\"{} {} {}\">\n", extent, f.origin[0],
                 f.origin[1], f.origin[2], f.spacing[0], f.spacing[1], f.spacing[2]);
  fmt::format_to(it, "    <FieldData>\n");
  auto scalar_field = [&](std::string_view name, std::string_view type, auto value) {
    fmt::format_to(it, "      <DataArray type=\"{}\" Name=\"{}\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n",
                   type, name, value);
  };
  scalar_field("TimeValue", "Float64", s.time);
  scalar_field("exposure_begin", "Float64", s.exposure->t_begin);
  scalar_field("exposure_end", "Float64", s.exposure->t_end);
  scalar_field("exposure_samples", "Int32", s.exposure->samples);
  fmt::format_to(it, "    </FieldData>\n    <Piece Extent=\"{}\">\n      <CellData Scalars=\"number_density\"{}>\n",
                 extent, s.velocity ? " Vectors=\"mean_velocity\"" : "");
  std::uint64_t offset = 0;
  for (const Array& a : f.arrays) {
    fmt::format_to(it, "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" "
                       "offset=\"{}\"/>\n", a.vtk_type(), a.name, a.components, offset);
    offset += 8 + a.bytes();
  }
  x += "      </CellData>\n    </Piece>\n  </ImageData>\n  <AppendedData encoding=\"raw\">\n   _";
  for (const Array& a : f.arrays) {
    const std::uint64_t n = a.bytes();
    x.append(reinterpret_cast<const char*>(&n), 8);
    x.append(a.data(), n);
  }
  x += "\n  </AppendedData>\n</VTKFile>\n";
  return x;
}

// NumPy format 1.0: one structured array of shape (ny, nx), the bin centres x, y, z first.
std::string npy(const FrameFields& f) {
  const core::GridGeometry& g = f.grid;
  std::vector<Array> arrays;
  for (int axis = 0; axis < 3; ++axis) {
    Array c{Array::f64, std::string(1, "xyz"[axis])};
    c.f.resize(g.size());
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        const Vec2 p = g.centre(ix, iy);
        c.f[g.index(ix, iy)] = axis == f.axes[0] ? p.x() : axis == f.axes[1] ? p.y() : f.origin[axis];
      }
    arrays.push_back(std::move(c));
  }
  arrays.insert(arrays.end(), f.arrays.begin(), f.arrays.end());
  std::string descr;
  std::size_t record = 0;
  for (const Array& a : arrays) {
    descr += fmt::format("('{}', '{}'{}), ", a.name, a.npy_type(), a.components > 1 ? fmt::format(", ({},)", a.components) : "");
    record += a.item() * a.components;
  }
  std::string header = fmt::format("{{'descr': [{}], 'fortran_order': False, 'shape': ({}, {}), }}", descr, g.ny, g.nx);
  header.append(63 - (10 + header.size()) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  const auto len = std::uint16_t(header.size());
  out.append(reinterpret_cast<const char*>(&len), 2);
  out += header;
  const std::size_t start = out.size();
  out.resize(start + record * g.size());
  char* p = out.data() + start;
  for (std::size_t b = 0; b < g.size(); ++b)
    for (const Array& a : arrays) {
      const std::size_t n = a.item() * a.components;
      std::memcpy(p, a.data() + b * n, n);
      p += n;
    }
  return out;
}

std::string frame_name(std::int64_t index, std::string_view ext) { return fmt::format("frame_{:06d}.{}", index, ext); }

class FieldsOutput final : public RunOutput {
public:
  explicit FieldsOutput(std::filesystem::path dir) : dir_(std::move(dir)) {}

  void start(const RunRecord&) override {
    make_folder();
    write_collection();
  }
  void checkpoint(io::ArchiveWriter& w) override {
    w.tag("fields");
    w.pod(std::uint64_t(entries_.size()));
    for (const Entry& e : entries_) {
      w.pod(e.index);
      w.pod(e.time);
    }
    w.pod(last_end_);
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag("fields");
    const auto n = r.get<std::uint64_t>();
    if (n > r.left() / 16) r.corrupt(fmt::format("{} field frames in {} bytes", n, r.left()));
    entries_.resize(n);
    for (Entry& e : entries_) {
      r.pod(e.index);
      r.pod(e.time);
    }
    r.pod(last_end_);
    make_folder();
    // Frames written after the checkpoint are written again by the resumed run; until then
    // they are not listed, and files of them are removed, so the folder and the collection
    // agree whatever the resumed run does.
    const std::int64_t first_new = entries_.empty() ? 0 : entries_.back().index + 1;
    static const std::regex numbered(R"(^frame_([0-9]{6,})\.(vti|npy)$)");
    std::error_code ec;
    std::vector<std::filesystem::path> stale;
    for (const auto& e : std::filesystem::directory_iterator(dir_ / "fields", ec)) {
      std::smatch m;
      const std::string name = e.path().filename().string();
      if (std::regex_match(name, m, numbered) && std::stoll(m[1].str()) >= first_new) stale.push_back(e.path());
    }
    for (const auto& p : stale) std::filesystem::remove(p, ec);
    write_collection();
  }
  void frame(std::int64_t index, const render::Snapshot& s) override {
    // A frame shows the exposure that ended last: written once, when it is new (the first
    // frame of a run has none yet).
    if (!s.exposure || !s.field("density") || s.exposure->t_end <= last_end_) return;
    const FrameFields f = frame_fields(s);
    io::write_text_atomically(dir_ / "fields" / frame_name(index, "vti"), vti(f, s));
    io::write_text_atomically(dir_ / "fields" / frame_name(index, "npy"), npy(f));
    entries_.push_back({index, s.time});
    last_end_ = s.exposure->t_end;
    write_collection();
  }
  void finish(const RunRecord&) override {}

private:
  struct Entry {
    std::int64_t index;
    double time;
  };

  void make_folder() {
    io::make_output_folder(dir_ / "fields");
  }
  void write_collection() const {
    std::string x = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "  <Collection>\n";
    for (const Entry& e : entries_)
      x += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"fields/{}\"/>\n", e.time,
                       frame_name(e.index, "vti"));
    x += "  </Collection>\n</VTKFile>\n";
    io::write_text_atomically(dir_ / "fields.pvd", x);
  }

  std::filesystem::path dir_;
  std::vector<Entry> entries_;
  double last_end_ = -std::numeric_limits<double>::infinity();  // the last written exposure's end
};

void declare(Schema& s) {
  s.table("output").add_bool(fields, false,
                             "write every frame's binned fields to fields/frame_NNNNNN.vti (VTK image data) and .npy "
                             "(NumPy), with the time series fields.pvd for ParaView");
}

std::unique_ptr<RunOutput> open(const OutputContext& c) {
  if (!c.scene.get(fields)) return nullptr;
  c.claim("fields.pvd");
  c.claim(kVtiFiles);
  c.claim(kNpyFiles);
  return std::make_unique<FieldsOutput>(c.dir);
}

}  // namespace

OutputEntry fields_output() {
  return {"fields", "fields/*.vti, *.npy and fields.pvd, every frame's binned fields", &declare, nullptr, &open};
}

}  // namespace grainflow::scenes
