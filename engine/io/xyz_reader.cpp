#include "engine/io/xyz_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>

#include "engine/core/error.hpp"

namespace grainflow::io {
namespace {

// Properties specs and Lattice values are quoted whole in messages, up to this length.
constexpr std::size_t kSpecChars = 160;

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

bool icontains(std::string_view hay, std::string_view needle) {
  return lower(hay).find(lower(needle)) != std::string::npos;
}

struct KeyValue {
  std::string key;  // lower case
  std::string value;
};

// key=value pairs of an extended-XYZ comment line; values may be "double quoted".
// Bare words (ASE boolean flags) are kept with an empty value.
std::vector<KeyValue> parse_comment(std::string_view s, const LineReader& in) {
  std::vector<KeyValue> out;
  std::size_t i = 0;
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (i < s.size()) {
    while (i < s.size() && blank(s[i])) ++i;
    if (i >= s.size()) break;
    const std::size_t k0 = i;
    while (i < s.size() && !blank(s[i]) && s[i] != '=') ++i;
    KeyValue kv{lower(s.substr(k0, i - k0)), {}};
    while (i < s.size() && blank(s[i])) ++i;
    if (i < s.size() && s[i] == '=') {
      ++i;
      while (i < s.size() && blank(s[i])) ++i;
      if (i < s.size() && (s[i] == '"' || s[i] == '\'')) {
        const char q = s[i++];
        const std::size_t end = s.find(q, i);
        if (end == std::string_view::npos)
          in.fail("unterminated quoted value of key '" + printable(kv.key) + "' in the extended-XYZ comment line");
        kv.value = std::string(s.substr(i, end - i));
        i = end + 1;
      } else {
        const std::size_t v0 = i;
        while (i < s.size() && !blank(s[i])) ++i;
        kv.value = std::string(s.substr(v0, i - v0));
      }
    }
    out.push_back(std::move(kv));
  }
  return out;
}

enum class Role { species, pos, radius, diameter, velocity, id, type, extra, ignored };

struct Property {
  std::string name;  // as written
  char kind;         // S R I L
  int ncols;
  Role role;
};

std::string describe(const std::vector<Property>& props) {
  std::string s;
  // Appended piece by piece ("" + std::string&& trips a GCC 12 -Wrestrict false positive).
  for (const auto& p : props) {
    if (!s.empty()) s.push_back(' ');
    s.append(printable(p.name)).append(1, ':').append(1, p.kind).append(1, ':').append(std::to_string(p.ncols));
  }
  return s;
}

std::vector<Property> parse_properties(const std::string& spec, const LineReader& in) {
  std::vector<std::string_view> parts;
  std::string_view sv(spec);
  for (std::size_t start = 0;;) {
    const std::size_t c = sv.find(':', start);
    parts.push_back(sv.substr(start, c == std::string_view::npos ? std::string_view::npos : c - start));
    if (c == std::string_view::npos) break;
    start = c + 1;
  }
  if (parts.size() % 3 != 0)
    in.fail("Properties=" + printable(spec, kSpecChars) + " is not a list of name:type:count triples");
  std::vector<Property> props;
  bool has_species = false;
  for (std::size_t i = 0; i < parts.size(); i += 3) {
    Property p;
    p.name = std::string(parts[i]);
    const std::string kind = lower(parts[i + 1]);
    std::int64_t n = 0;
    if (p.name.empty() || kind.size() != 1 || std::string_view("sril").find(kind[0]) == std::string_view::npos ||
        !parse_int64(parts[i + 2], n) || n < 1 || n > 1000)
      in.fail("bad Properties entry '" + printable(parts[i]) + ":" + printable(parts[i + 1]) + ":" +
              printable(parts[i + 2]) + "'; expected name:S|R|I|L:count");
    p.kind = static_cast<char>(std::toupper(kind[0]));
    p.ncols = static_cast<int>(n);
    const std::string nm = lower(p.name);
    const bool numeric = p.kind != 'S';
    if ((nm == "species" || nm == "element") && p.ncols == 1)
      p.role = Role::species, has_species = true;
    else if ((nm == "pos" || nm == "positions") && numeric && (p.ncols == 2 || p.ncols == 3))
      p.role = Role::pos;
    else if ((nm == "radius" || nm == "radii") && numeric && p.ncols == 1)
      p.role = Role::radius;
    else if ((nm == "diameter" || nm == "diameters") && numeric && p.ncols == 1)
      p.role = Role::diameter;
    else if ((nm == "velo" || nm == "vel" || nm == "velocity" || nm == "velocities") && numeric &&
             (p.ncols == 2 || p.ncols == 3))
      p.role = Role::velocity;
    else if ((nm == "id" || nm == "ids") && p.kind == 'I' && p.ncols == 1)
      p.role = Role::id;
    else if (nm == "type" && p.kind == 'I' && p.ncols == 1)
      p.role = Role::type;
    else
      p.role = numeric ? Role::extra : Role::ignored;
    props.push_back(std::move(p));
  }
  for (auto& p : props)
    if (p.role == Role::type && has_species) p.role = Role::extra;
  const auto count = [&](Role r) { return std::count_if(props.begin(), props.end(), [&](const Property& p) { return p.role == r; }); };
  if (count(Role::pos) != 1)
    in.fail("Properties=" + printable(spec, kSpecChars) + " has no position property (pos:R:3 or pos:R:2)");
  for (Role r : {Role::species, Role::radius, Role::diameter, Role::velocity, Role::id, Role::type})
    if (count(r) > 1) in.fail("Properties=" + printable(spec, kSpecChars) + " names the same quantity twice");
  if (count(Role::radius) && count(Role::diameter))
    in.fail("Properties=" + printable(spec, kSpecChars) + " has both a radius and a diameter column");
  return props;
}

std::vector<double> parse_numbers(const std::string& value, std::size_t n, const char* key, const LineReader& in) {
  std::vector<std::string_view> tok;
  split_ws(value, tok);
  std::vector<double> out(tok.size());
  for (std::size_t i = 0; i < tok.size(); ++i)
    if (!parse_double(tok[i], out[i]) || !std::isfinite(out[i]))
      in.fail(std::string(key) + "=\"" + printable(value, kSpecChars) + "\": " + quote_token(tok[i]) +
              " is not a finite number");
  if (out.size() != n)
    in.fail(std::string(key) + "=\"" + printable(value, kSpecChars) + "\": expected " + std::to_string(n) +
            " numbers, got " + std::to_string(out.size()));
  return out;
}

bool parse_bool(std::string_view t, bool& out) {
  const std::string l = lower(t);
  if (l == "t" || l == "true" || l == "1") return out = true, true;
  if (l == "f" || l == "false" || l == "0") return out = false, true;
  return false;
}

}  // namespace

XyzReader::XyzReader(std::string path) : in_(std::move(path)) {}
XyzReader::XyzReader(LineReader&& in) : in_(std::move(in)) {}

int XyzReader::species_type(std::string_view s) {
  if (mode_ == SpeciesMode::unknown) {
    std::int64_t v;
    mode_ = parse_int64(s, v) ? SpeciesMode::numeric : SpeciesMode::named;
  }
  if (mode_ == SpeciesMode::numeric) {
    std::int64_t v;
    if (!parse_int64(s, v) || v < 0 || v > 1000000)
      in_.fail("species " + quote_token(s) +
               " is not a type number, but the first species of this file was a number; "
               "expected all numbers or all names");
    return static_cast<int>(v);
  }
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == s) return static_cast<int>(i) + 1;
  names_.emplace_back(s);
  return static_cast<int>(names_.size());
}

bool XyzReader::next(ParticleFrame& f) {
  return read_frame_or_truncated(in_, [&] { return read_frame(f); });
}

bool XyzReader::read_frame(ParticleFrame& f) {
  std::string_view line;
  // Particle count (blank lines between frames and at the end are tolerated).
  do {
    if (!in_.next(line)) return false;
  } while (trim(line).empty());
  split_ws(line, tokens_);
  std::int64_t n = -1;
  if (tokens_.size() != 1 || !parse_int64(tokens_[0], n) || n < 0)
    in_.fail("expected the particle count of an XYZ frame (one non-negative integer), got " + quote_token(trim(line)));
  check_particle_limit(in_, n);
  const long count_line = in_.line_number();

  if (!in_.next(line))
    in_.fail_truncated("file ends after the particle count; expected a comment line and " + std::to_string(n) +
                                " particle lines");
  f.clear();
  const std::string comment(line);
  const bool extended = icontains(comment, "properties=") || icontains(comment, "lattice=");
  std::vector<Property> props;
  if (extended) {
    std::optional<std::string> properties;
    std::vector<double> lattice, origin;
    for (const auto& kv : parse_comment(comment, in_)) {
      if (kv.key == "properties") {
        properties = kv.value;
      } else if (kv.key == "lattice") {
        lattice = parse_numbers(kv.value, 9, "Lattice", in_);
      } else if (kv.key == "origin") {
        origin = parse_numbers(kv.value, 3, "Origin", in_);
      } else if (kv.key == "time") {
        if (!parse_double(kv.value, f.time) || !std::isfinite(f.time))
          in_.fail("Time=" + printable(kv.value) + " is not a finite number");
      } else if (kv.key == "timestep" || kv.key == "step") {
        if (!parse_int64(kv.value, f.timestep))
          in_.fail(kv.key + "=" + printable(kv.value) + " is not an integer");
      } else if (kv.key == "pbc") {
        std::vector<std::string_view> t;
        split_ws(kv.value, t);
        if (t.size() != 3 || !parse_bool(t[0], f.periodic[0]) || !parse_bool(t[1], f.periodic[1]) ||
            !parse_bool(t[2], f.periodic[2]))
          in_.fail("pbc=\"" + printable(kv.value) + "\": expected three of T/F");
      }
    }
    props = parse_properties(properties.value_or("species:S:1:pos:R:3"), in_);
    if (!lattice.empty()) {
      const Vec3 o = origin.empty() ? Vec3::Zero() : Vec3(origin[0], origin[1], origin[2]);
      const Vec3 a(lattice[0], lattice[1], lattice[2]), b(lattice[3], lattice[4], lattice[5]),
          c(lattice[6], lattice[7], lattice[8]);
      f.has_box = true;
      f.box_lo = f.box_hi = o;
      for (int corner = 1; corner < 8; ++corner) {
        const Vec3 p = o + ((corner & 1) ? a : Vec3::Zero()) + ((corner & 2) ? b : Vec3::Zero()) +
                       ((corner & 4) ? c : Vec3::Zero());
        f.box_lo = f.box_lo.cwiseMin(p);
        f.box_hi = f.box_hi.cwiseMax(p);
      }
      f.triclinic = a.y() != 0 || a.z() != 0 || b.x() != 0 || b.z() != 0 || c.x() != 0 || c.y() != 0;
      if (f.triclinic && a.y() == 0 && a.z() == 0 && b.z() == 0) f.tilt = {b.x(), c.x(), c.y()};
      // Finite vectors can still add up past the largest double (1e308 + 1e308).
      if (!f.box_lo.allFinite() || !f.box_hi.allFinite())
        in_.fail("Lattice and Origin give a box whose corners are not finite numbers (beyond 1.8e308)");
    }
  }

  // Column layout of this frame.
  int expected_cols = 0;
  for (const auto& p : props) expected_cols += p.ncols;
  const std::size_t count = static_cast<std::size_t>(n);
  // A plain XYZ line has at least 4 columns (species x y z); how many is seen on the first.
  const std::size_t first = plausible_particles(in_, n, count_line, extended ? expected_cols : 4);
  bool pos2d = false, have_vel = false;
  if (extended) {
    for (const auto& p : props) {
      if (p.role == Role::velocity) have_vel = true;
      if (p.role == Role::pos) pos2d = p.ncols == 2;
      if (p.role != Role::extra) continue;
      for (int k = 0; k < p.ncols; ++k) {
        std::string name = p.name;
        if (p.ncols == 3) name += std::string("_") + "xyz"[k];
        else if (p.ncols > 1) name.append(1, '_').append(std::to_string(k));  // not "_" + ...: GCC 12 -Wrestrict
        f.extra.emplace_back(std::move(name), std::vector<double>());
      }
    }
  }
  resize_particles(f, first, kDefaultRadius, have_vel);

  const bool have_id = std::any_of(props.begin(), props.end(), [](const Property& p) { return p.role == Role::id; });
  for (std::size_t i = 0; i < count; ++i) {
    if (!in_.next(line))
      in_.fail_truncated("file ends after " + std::to_string(i) + " of the " + std::to_string(n) +
               " particle lines announced on line " + std::to_string(count_line) + " (truncated frame?)");
    if (i == f.size()) resize_particles(f, grown_size(i, count), kDefaultRadius, have_vel);
    split_ws(line, tokens_);
    if (!extended) {
      if (i == 0) {
        if (tokens_.size() < 4)
          in_.fail("expected at least 4 columns (species x y z) in a plain XYZ particle line, got " +
                   std::to_string(tokens_.size()));
        expected_cols = static_cast<int>(tokens_.size());
        for (int c = 5; c <= expected_cols; ++c)
          f.extra.emplace_back("column" + std::to_string(c), std::vector<double>(f.size()));
      }
      if (static_cast<int>(tokens_.size()) != expected_cols)
        in_.fail("expected " + std::to_string(expected_cols) + " columns (species x y z" +
                 (expected_cols > 4 ? " + " + std::to_string(expected_cols - 4) + " more, as on the frame's first particle line" : std::string()) +
                 "), got " + std::to_string(tokens_.size()));
      f.type[i] = species_type(tokens_[0]);
      for (int k = 0; k < 3; ++k)
        if (!parse_double(tokens_[1 + k], f.position[i][k]) || !std::isfinite(f.position[i][k]))
          in_.fail(std::string("position ") + "xyz"[k] + " of particle " + std::to_string(i + 1) + ": expected a finite number, got " + quote_token(tokens_[1 + k]));
      for (int c = 4; c < expected_cols; ++c)
        if (!parse_double(tokens_[c], f.extra[c - 4].second[i]))
          in_.fail("column " + std::to_string(c + 1) + ": expected a number, got " + quote_token(tokens_[c]));
      f.id[i] = static_cast<std::int64_t>(i) + 1;
      continue;
    }
    if (static_cast<int>(tokens_.size()) != expected_cols)
      in_.fail("expected " + std::to_string(expected_cols) + " columns (" + describe(props) + "), got " +
               std::to_string(tokens_.size()));
    int col = 0;
    std::size_t slot = 0;
    for (const auto& p : props) {
      auto number = [&](int k, bool finite) {
        double v;
        const auto tok = tokens_[col + k];
        if (p.kind == 'L') {
          bool b;
          if (!parse_bool(tok, b)) in_.fail("column " + std::to_string(col + k + 1) + " (" + printable(p.name) + "): expected T or F, got " + quote_token(tok));
          return b ? 1.0 : 0.0;
        }
        if (!parse_double(tok, v) || (finite && !std::isfinite(v)))
          in_.fail("column " + std::to_string(col + k + 1) + " (" + printable(p.name) + "): expected a " +
                   (finite ? "finite " : "") + "number, got " + quote_token(tok));
        return v;
      };
      switch (p.role) {
        case Role::species: f.type[i] = species_type(tokens_[col]); break;
        case Role::pos:
          for (int k = 0; k < p.ncols; ++k) f.position[i][k] = number(k, true);
          break;
        case Role::velocity:
          for (int k = 0; k < p.ncols; ++k) f.velocity[i][k] = number(k, true);
          break;
        case Role::radius:
        case Role::diameter: {
          const double v = number(0, true);
          if (v < 0) in_.fail("column " + std::to_string(col + 1) + " (" + printable(p.name) + "): negative value " + quote_token(tokens_[col]));
          f.radius[i] = p.role == Role::radius ? v : 0.5 * v;
          break;
        }
        case Role::id:
        case Role::type: {
          std::int64_t v;
          if (!parse_int64(tokens_[col], v))
            in_.fail("column " + std::to_string(col + 1) + " (" + printable(p.name) + "): expected an integer, got " + quote_token(tokens_[col]));
          if (p.role == Role::id) f.id[i] = v;
          else f.type[i] = static_cast<int>(v);
          break;
        }
        case Role::extra:
          for (int k = 0; k < p.ncols; ++k) f.extra[slot++].second[i] = number(k, false);
          break;
        case Role::ignored: break;
      }
      col += p.ncols;
    }
    if (!have_id) f.id[i] = static_cast<std::int64_t>(i) + 1;
  }

  f.type_names = names_;
  f.dim = (pos2d || (count > 0 && std::all_of(f.position.begin(), f.position.end(),
                                                [](const Vec3& p) { return p.z() == 0.0; })))
              ? 2
              : 3;
  return true;
}

}  // namespace grainflow::io
