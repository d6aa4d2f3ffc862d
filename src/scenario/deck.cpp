#include "scenario/deck.hpp"

#include <filesystem>
#include <limits>
#include <cmath>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace ejecta::scenario {
namespace {

// Reads typed fields out of one table and remembers which keys were used, so that what is left
// is reported as unknown.
class Reader {
 public:
  Reader(const toml::table* t, std::string path) : t_(t), path_(std::move(path)) {}
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  void num(const std::string& k, double& v) {
    used_.insert(k);
    if (!t_) return;
    const auto* n = t_->get(k);
    if (!n) return;
    if (auto d = n->value<double>()) v = *d;
    else throw InputError(key(k), "must be a number");
    if (!std::isfinite(v)) throw InputError(key(k), "must be a finite number");
  }
  void str(const std::string& k, std::string& v) {
    used_.insert(k);
    if (!t_) return;
    if (const auto* n = t_->get(k)) {
      if (auto s = n->value<std::string>()) v = *s;
      else throw InputError(key(k), "must be a string");
    }
  }
  void boolean(const std::string& k, bool& v) {
    used_.insert(k);
    if (!t_) return;
    if (const auto* n = t_->get(k)) {
      if (n->is_boolean()) v = *n->value<bool>();   // strictly: value<bool>() would take 1 as true
      else throw InputError(key(k), "must be true or false");
    }
  }
  void numList(const std::string& k, std::vector<double>& v) {
    used_.insert(k);
    if (!t_) return;
    const auto* n = t_->get(k);
    if (!n) return;
    const auto* arr = n->as_array();
    if (!arr) throw InputError(key(k), "must be a list of numbers");
    v.clear();
    for (const auto& e : *arr) {
      auto d = e.value<double>();
      if (!d) throw InputError(key(k), "must be a list of numbers");
      v.push_back(*d);
    }
  }
  void mark(const std::string& k) { used_.insert(k); }
  const toml::table* sub(const std::string& k) {
    used_.insert(k);
    if (!t_) return nullptr;
    const auto* n = t_->get(k);
    if (!n) return nullptr;
    if (!n->as_table()) throw InputError(key(k), "must be a table [" + key(k) + "]");
    return n->as_table();
  }
  void finish() const {
    if (!t_) return;
    for (const auto& [k, v] : *t_)
      if (!used_.count(std::string(k.str()))) throw InputError(key(std::string(k.str())), "unknown key");
  }

 private:
  const toml::table* t_;
  std::string path_;
  std::set<std::string> used_;
};

void range(const std::string& key, double v, double lo, double hi, const char* unit, bool lo_open = false) {
  if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi))
    throw InputError(key, fmt::format("{:g} {} is out of range; valid {}{:g}, {:g}] {}", v, unit, lo_open ? "(" : "[", lo, hi, unit));
}

void oneOf(const std::string& key, const std::string& v, std::initializer_list<const char*> allowed) {
  for (const char* a : allowed)
    if (v == a) return;
  std::string list;
  for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
  throw InputError(key, fmt::format("'{}' is not valid; valid: {}", v, list));
}

void applyOverride(toml::table& root, const std::string& ov) {
  const auto eq = ov.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--set", fmt::format("'{}' is not KEY=VALUE", ov));
  const std::string path = ov.substr(0, eq), value = ov.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    try {
      parsed = toml::parse("v = \"" + value + "\"");   // a bare word is a string
    } catch (const toml::parse_error&) {
      throw InputError(path, fmt::format("'{}' is not a valid value", value));
    }
  }
  toml::table* t = &root;
  std::size_t start = 0;
  for (;;) {
    const auto dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (dot == std::string::npos) {
      t->insert_or_assign(part, *parsed.get("v"));
      return;
    }
    auto* next = t->get(part);
    if (!next) {
      t->insert_or_assign(part, toml::table{});
      next = t->get(part);
    }
    start = dot + 1;
    // an array of tables ([[soil]]) takes an index: soil.0.moisture
    if (auto* arr = next->as_array()) {
      const auto dot2 = path.find('.', start);
      const std::string index = path.substr(start, dot2 == std::string::npos ? std::string::npos : dot2 - start);
      const bool digits = !index.empty() && index.size() <= 9 && index.find_first_not_of("0123456789") == std::string::npos;
      if (!digits || dot2 == std::string::npos)
        throw InputError(path, fmt::format("'{}' is a list: name an entry by its index, {}.0.KEY (valid 0 to {})", part, part, arr->size() - 1));
      const auto n = std::stoul(index);
      if (n >= arr->size() || !arr->get(n)->as_table())
        throw InputError(path, fmt::format("'{}' has {} entries; valid indices 0 to {}", part, arr->size(), arr->size() - 1));
      next = arr->get(n);
      start = dot2 + 1;
    }
    if (!next->as_table()) throw InputError(path, "is not inside a table");
    t = next->as_table();
  }
}

void readSoil(const toml::table* t, const std::string& path, SoilSpec& s) {
  Reader r(t, path);
  r.str("name", s.name);
  r.num("wet_density_kg_m3", s.wet_density_kg_m3);
  r.num("dry_density_kg_m3", s.dry_density_kg_m3);
  r.num("moisture", s.moisture);
  r.num("top_m", s.top_m);
  r.num("bottom_m", s.bottom_m);
  r.num("radius_m", s.radius_m);
  r.str("water_eos", s.water_eos);
  r.num("plateau_scale", s.plateau_scale);
  r.num("thermal_gamma", s.thermal_gamma);
  r.finish();
  if ((s.wet_density_kg_m3 > 0.0) == (s.dry_density_kg_m3 > 0.0))
    throw InputError(path, "give exactly one of wet_density_kg_m3 and dry_density_kg_m3 (> 0)");
  range(path + ".moisture", s.moisture, 0.0, 1.0, "-");
  if (!(s.top_m > s.bottom_m)) throw InputError(path + ".top_m", "must be above bottom_m");
  range(path + ".radius_m", s.radius_m, 0.0, 1e3, "m");
  oneOf(path + ".water_eos", s.water_eos, {"awg", "alt"});
  range(path + ".plateau_scale", s.plateau_scale, 0.0, 10.0, "-");
  if (s.thermal_gamma != -1.0) range(path + ".thermal_gamma", s.thermal_gamma, 0.0, 4.0, "- (or -1: from the constituents)");
}

}  // namespace

Deck parseDeck(const std::string& text, const std::vector<std::string>& overrides, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw InputError(source, fmt::format("TOML syntax error at line {}: {}", e.source().begin.line, e.description()));
  }
  for (const auto& ov : overrides) applyOverride(root, ov);

  Deck d;
  Reader top(&root, "");
  top.str("title", d.title);
  top.str("geometry", d.geometry);
  oneOf("geometry", d.geometry, {"axisymmetric", "3d-quarter"});
  top.boolean("gravity", d.gravity);
  top.num("end_time_s", d.end_time_s);
  range("end_time_s", d.end_time_s, 0.0, 1.0, "s", true);
  top.num("cfl", d.cfl);
  range("cfl", d.cfl, 0.05, 0.9, "-");

  {
    Reader r(top.sub("mesh"), "mesh");
    auto& m = d.mesh;
    r.num("cell_size_m", m.cell_size_m);
    r.num("grading", m.grading);
    r.num("core_radius_m", m.core_radius_m);
    r.num("core_bottom_m", m.core_bottom_m);
    r.num("core_top_m", m.core_top_m);
    r.num("domain_radius_m", m.domain_radius_m);
    r.num("domain_bottom_m", m.domain_bottom_m);
    r.num("domain_top_m", m.domain_top_m);
    r.finish();
    range("mesh.cell_size_m", m.cell_size_m, 1e-4, 0.1, "m");
    range("mesh.grading", m.grading, 1.0, 1.5, "-");
    range("mesh.core_radius_m", m.core_radius_m, m.cell_size_m, m.domain_radius_m, "m");
    if (!(m.domain_bottom_m <= m.core_bottom_m && m.core_bottom_m < m.core_top_m && m.core_top_m <= m.domain_top_m))
      throw InputError("mesh.core_bottom_m", "need domain_bottom_m <= core_bottom_m < core_top_m <= domain_top_m");
  }
  top.mark("soil");   // an array of tables, read below
  if (const auto* arr = root.get("soil") ? root.get("soil")->as_array() : nullptr) {
    int i = 0;
    for (const auto& e : *arr) {
      if (!e.as_table()) throw InputError("soil", "must be [[soil]] tables");
      SoilSpec s;
      readSoil(e.as_table(), fmt::format("soil[{}]", i++), s);
      d.soil.push_back(s);
    }
  }
  if (d.soil.empty()) throw InputError("soil", "at least one [[soil]] layer is needed");
  {
    Reader r(top.sub("backfill"), "backfill");
    auto& b = d.backfill;
    r.boolean("enabled", b.enabled);
    r.num("radius_m", b.radius_m);
    r.num("wet_density_kg_m3", b.wet_density_kg_m3);
    r.num("dry_density_kg_m3", b.dry_density_kg_m3);
    r.num("moisture", b.moisture);
    r.finish();
    if (b.enabled && (b.wet_density_kg_m3 > 0.0) == (b.dry_density_kg_m3 > 0.0))
      throw InputError("backfill", "give exactly one of wet_density_kg_m3 and dry_density_kg_m3 (> 0)");
    range("backfill.moisture", b.moisture, 0.0, 1.0, "-");
  }
  {
    Reader r(top.sub("charge"), "charge");
    auto& c = d.charge;
    r.str("explosive", c.explosive);
    r.num("mass_kg", c.mass_kg);
    r.str("shape", c.shape);
    r.num("height_to_diameter", c.height_to_diameter);
    r.num("depth_of_burial_m", c.depth_of_burial_m);
    r.str("detonation", c.detonation);
    r.finish();
    oneOf("charge.explosive", c.explosive, {"C4", "CompB", "TNT"});
    range("charge.mass_kg", c.mass_kg, 0.0, 1000.0, "kg", true);
    oneOf("charge.shape", c.shape, {"cylinder", "sphere", "box"});
    if (c.shape == "box" && d.geometry != "3d-quarter")
      throw InputError("charge.shape", "'box' needs geometry = \"3d-quarter\" (2D axisymmetric: cylinder or sphere)");
    range("charge.height_to_diameter", c.height_to_diameter, 0.05, 20.0, "-");
    range("charge.depth_of_burial_m", c.depth_of_burial_m, 0.0, 10.0, "m");
    oneOf("charge.detonation", c.detonation, {"bottom", "centre", "top"});
  }
  {
    Reader r(top.sub("early"), "early");
    auto& e = d.early;
    r.boolean("enabled", e.enabled);
    r.num("cells_per_charge_height", e.cells_per_charge_height);
    r.num("map_time_s", e.map_time_s);
    r.num("signal_speed_m_s", e.signal_speed_m_s);
    r.num("block_margin_m", e.block_margin_m);
    r.finish();
    range("early.cells_per_charge_height", e.cells_per_charge_height, 4.0, 200.0, "-");
    range("early.map_time_s", e.map_time_s, 0.0, 1e-3, "s");
    range("early.signal_speed_m_s", e.signal_speed_m_s, 1000.0, 20000.0, "m/s");
    if (e.block_margin_m != 0.0) range("early.block_margin_m", e.block_margin_m, 0.01, 2.0, "m (or 0: automatic)");
  }
  {
    Reader r(top.sub("air"), "air");
    r.num("pressure_pa", d.air_pressure_pa);
    r.num("density_kg_m3", d.air_density_kg_m3);
    r.finish();
    range("air.pressure_pa", d.air_pressure_pa, 1.0, 1e7, "Pa");
    range("air.density_kg_m3", d.air_density_kg_m3, 1e-3, 100.0, "kg/m3");
  }
  {
    Reader r(top.sub("target"), "target");
    auto& t = d.target;
    r.str("kind", t.kind);
    r.num("radius_m", t.radius_m);
    r.num("inner_radius_m", t.inner_radius_m);
    r.num("thickness_m", t.thickness_m);
    r.num("standoff_m", t.standoff_m);
    r.num("mass_kg", t.mass_kg);
    r.str("motion", t.motion);
    r.num("friction", t.friction);
    r.num("half_length_m", t.half_length_m);
    r.num("half_width_m", t.half_width_m);
    r.num("apex_angle_deg", t.apex_angle_deg);
    r.finish();
    range("target.friction", t.friction, 0.0, 2.0, "-");
    oneOf("target.kind", t.kind, {"disc", "annulus", "rectangle", "v", "none"});
    if ((t.kind == "rectangle" || t.kind == "v") && d.geometry != "3d-quarter")
      throw InputError("target.kind", fmt::format("'{}' needs geometry = \"3d-quarter\" (2D axisymmetric: disc or annulus)", t.kind));
    range("target.half_length_m", t.half_length_m, 0.0, d.mesh.domain_radius_m, "m", true);
    range("target.half_width_m", t.half_width_m, 0.0, d.mesh.domain_radius_m, "m", true);
    range("target.apex_angle_deg", t.apex_angle_deg, 30.0, 180.0, "degrees");
    oneOf("target.motion", t.motion, {"free", "fixed"});
    if (t.kind != "none") {
      range("target.radius_m", t.radius_m, 0.0, d.mesh.domain_radius_m, "m", true);
      range("target.inner_radius_m", t.inner_radius_m, 0.0, t.radius_m, "m");
      range("target.thickness_m", t.thickness_m, d.mesh.cell_size_m, 1.0, "m");
      range("target.standoff_m", t.standoff_m, 0.0, d.mesh.domain_top_m, "m");
      if (t.motion == "free") range("target.mass_kg", t.mass_kg, 0.0, 1e6, "kg", true);
      if (t.standoff_m + t.thickness_m > d.mesh.domain_top_m - 2.0 * d.mesh.cell_size_m)
        throw InputError("target.standoff_m", "the plate must lie inside the domain (raise mesh.domain_top_m)");
    }
  }
  {
    Reader r(top.sub("output"), "output");
    auto& o = d.output;
    r.num("history_interval_s", o.history_interval_s);
    r.numList("profile_times_s", o.profile_times_s);
    r.numList("field_times_s", o.field_times_s);
    r.num("surface_soil_fraction", o.surface_soil_fraction);
    if (const auto* n = root.get("output") ? root.get("output")->as_table() : nullptr) {
      r.mark("gauges_m");
      if (const auto* g = n->get("gauges_m")) {
        const auto* arr = g->as_array();
        if (!arr) throw InputError("output.gauges_m", "must be a list of [r, z] pairs");
        for (const auto& e : *arr) {
          const auto* pt = e.as_array();
          if (!pt || pt->size() != 2 || !(*pt)[0].value<double>() || !(*pt)[1].value<double>())
            throw InputError("output.gauges_m", "must be a list of [r, z] pairs (m)");
          o.gauges_m.push_back({*(*pt)[0].value<double>(), *(*pt)[1].value<double>()});
        }
      }
    }
    r.finish();
    range("output.history_interval_s", o.history_interval_s, 1e-8, 1.0, "s");
    range("output.surface_soil_fraction", o.surface_soil_fraction, 0.01, 1.0, "-");
    // output times: positive and increasing (times after end_time_s are simply not reached: a run
    // shortened with --set end_time_s keeps its deck's later times)
    for (const auto& [key, times] : {std::pair<const char*, const std::vector<double>*>{"output.profile_times_s", &o.profile_times_s},
                                     {"output.field_times_s", &o.field_times_s}}) {
      double prev = 0.0;
      for (const double t : *times) {
        if (!(t > prev) || !std::isfinite(t))
          throw InputError(key, fmt::format("{:g} s is out of range; valid: increasing times > 0 s", t));
        prev = t;
      }
    }
    for (const auto& g : o.gauges_m) {
      if (!std::isfinite(g[0]) || !std::isfinite(g[1]) || g[0] < 0.0 || g[0] > d.mesh.domain_radius_m || g[1] < d.mesh.domain_bottom_m || g[1] > d.mesh.domain_top_m)
        throw InputError("output.gauges_m", fmt::format("gauge ({:g}, {:g}) m is outside the domain", g[0], g[1]));
    }
  }
  top.finish();

  // The charge must sit inside the soil and the domain.
  const double top_of_charge = -d.charge.depth_of_burial_m;
  if (top_of_charge - 0.2 < d.mesh.domain_bottom_m)
    throw InputError("charge.depth_of_burial_m", "the charge lies outside (or too near the bottom of) the domain");
  // The soil's geometry must mean what the deck says. The ground is z = 0: the depth of burial,
  // the standoff and the backfill are measured from it, so the highest layer's top is 0. Layers
  // lie inside the domain and do not overlap, and the charge is buried in one of them.
  double ground = -std::numeric_limits<double>::infinity();
  bool charge_in_soil = false;
  for (std::size_t i = 0; i < d.soil.size(); ++i) {
    const auto& l = d.soil[i];
    const std::string key = fmt::format("soil.{}", i);
    if (l.bottom_m < d.mesh.domain_bottom_m - 1e-9 || l.top_m > d.mesh.domain_top_m + 1e-9)
      throw InputError(key + ".top_m", fmt::format("the layer [{:g}, {:g}] m lies outside the domain [{:g}, {:g}] m", l.bottom_m, l.top_m,
                                                   d.mesh.domain_bottom_m, d.mesh.domain_top_m));
    ground = std::max(ground, l.top_m);
    for (std::size_t j = 0; j < i; ++j) {
      const auto& o = d.soil[j];
      if (l.top_m > o.bottom_m + 1e-9 && o.top_m > l.bottom_m + 1e-9)
        throw InputError(key + ".top_m", fmt::format("the layer [{:g}, {:g}] m overlaps soil.{} [{:g}, {:g}] m; stack layers top to bottom", l.bottom_m,
                                                     l.top_m, j, o.bottom_m, o.top_m));
    }
    const double zc = top_of_charge - 1e-9;
    if (zc < l.top_m + 1e-9 && zc > l.bottom_m) charge_in_soil = true;
  }
  if (!d.soil.empty() && std::abs(ground) > 1e-9)
    throw InputError("soil.0.top_m", fmt::format("the highest soil layer's top is {:g} m; the ground is z = 0 m (the depth of burial, the "
                                                 "standoff and the backfill are measured from it), so it must be 0",
                                                 ground));
  if (!d.soil.empty() && !charge_in_soil)
    throw InputError("charge.depth_of_burial_m", "the charge's top is not inside any soil layer");
  std::stringstream js;
  js << toml::json_formatter{root};
  d.echo = nlohmann::json::parse(js.str());
  return d;
}

Deck loadDeck(const std::string& path, const std::vector<std::string>& overrides) {
  // A deck is a small text file: a device, a FIFO or a huge file is refused before it is read
  // (reading /dev/zero would otherwise grow without bound).
  constexpr std::uintmax_t kMaxDeckBytes = 1u << 20;
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
    throw InputError("deck", fmt::format("'{}' is not a regular file", path));
  if (const auto size = std::filesystem::file_size(path, ec); !ec && size > kMaxDeckBytes)
    throw InputError("deck", fmt::format("'{}' is {} bytes; a deck is at most {} bytes", path, size, kMaxDeckBytes));
  const auto text = io::readWholeFile(path);
  if (!text) throw InputError("deck", fmt::format("cannot read '{}'", path));
  return parseDeck(*text, overrides, path);
}

}  // namespace ejecta::scenario
