#include "scenario/deck.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <variant>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace ejecta::scenario {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Where a key's value lives in a Deck (layer: the index of the [[soil]] entry).
using FieldRef = std::variant<double*, std::string*, bool*, std::vector<double>*, std::vector<std::vector<double>>*>;
using FieldOf = FieldRef (*)(Deck&, std::size_t layer);

template <auto M>
FieldRef top(Deck& d, std::size_t) { return &(d.*M); }
template <auto S, auto M>
FieldRef in(Deck& d, std::size_t) { return &((d.*S).*M); }
template <auto M>
FieldRef layer(Deck& d, std::size_t i) { return &(d.soil[i].*M); }

struct Key {
  std::string section;   // "" (top level), a table ("mesh"), or "soil" (a list of tables)
  std::string name;      // the key inside its section
  FieldOf field;
  DeckKeyInfo info;
};

Key number(std::string section, std::string name, FieldOf f, std::string unit, Range r, std::string help, std::optional<double> special = {}) {
  Key k{std::move(section), std::move(name), f, {}};
  k.info.type = KeyType::Number;
  k.info.unit = std::move(unit);
  k.info.range = r;
  k.info.special = special;
  k.info.help = std::move(help);
  return k;
}
Key text(std::string section, std::string name, FieldOf f, std::vector<std::string> choices, std::string help) {
  Key k{std::move(section), std::move(name), f, {}};
  k.info.type = KeyType::Text;
  k.info.choices = std::move(choices);
  k.info.help = std::move(help);
  return k;
}
Key flag(std::string section, std::string name, FieldOf f, std::string help) {
  Key k{std::move(section), std::move(name), f, {}};
  k.info.type = KeyType::Boolean;
  k.info.help = std::move(help);
  return k;
}
Key list(std::string section, std::string name, FieldOf f, KeyType type, std::string unit, Range r, std::string help) {
  Key k{std::move(section), std::move(name), f, {}};
  k.info.type = type;
  k.info.unit = std::move(unit);
  k.info.range = r;
  k.info.help = std::move(help);
  return k;
}

// Static ranges: what the key can mean on its own. Ranges that depend on other keys (the core
// inside the domain, the plate inside the domain, a layer holding the charge) are checked after
// the whole deck is read (checkConsistency), naming the key.
std::vector<Key> makeKeys() {
  using materials::kMoistureRange, materials::kPlateauScaleRange, materials::kThermalGammaRange, materials::kShearModulusCapRange,
      materials::kMinPoissonRatioRange;
  const Range any_length{-100.0, 100.0};
  const Range density{0.0, 1e5};
  std::vector<Key> k{
      text("", "title", top<&Deck::title>, {}, "free text, shown in outputs"),
      text("", "geometry", top<&Deck::geometry>, {"axisymmetric", "3d-quarter"},
           "2D r-z, or 3D quarter symmetry (x, y >= 0 symmetry planes, z up; radii in the deck are from the z axis)"),
      flag("", "gravity", top<&Deck::gravity>, "body force -9.81 m/s2 on the flow and the plate"),
      number("", "end_time_s", top<&Deck::end_time_s>, "s", {0.0, 1.0, true}, "simulated time (not within the early time: at least its map time)"),
      number("", "cfl", top<&Deck::cfl>, "-", {0.05, 0.9},
             "Courant number of each sweep (0.30 since solver revision 15, chosen by the Reuss mixture's step error; 0.45 before)"),
      number("", "fragment_fold", top<&Deck::fragment_fold>, "-", {0.0, 1e-8},
             "a material under this fraction of a cell's volume is folded into the cell's other materials (mass, momentum and energy kept; "
             "summary.json books each material's folded mass); 0: never (docs/solver.md, Fragments)"),
      text("", "mixture_stiffness", top<&Deck::mixture_stiffness>, {"frozen", "reuss"},
           "a mixed cell's stiffness in the faces' impedance and the time step: the Reuss modulus the closure answers with plus its "
           "dilution stiffness, a shock impedance floor and the soft fraction's closing in the step (the default since solver revision 15), "
           "or the frozen (Voigt) sum, the default up to revision 14, whose step a trace of sand in gas sets (docs/solver.md, The mixture's "
           "stiffness)"),
      text("", "interface_remap", top<&Deck::interface_remap>, {"thinc", "thinc-bvd"},
           "how the remap moves a mixed cell's materials: THINC's sharp profile wherever the neighbours bracket the cell (it stripes a "
           "dust of sand in gas), or the profile on interfaces (near-pure fractions on both sides within two cells) and elsewhere only where "
           "it leaves smaller jumps at the donor's faces than the donor mean (BVD: a dust stays a dust; experimental; docs/solver.md, "
           "Interfaces and dust)"),
      flag("", "outflow_readmits_products", top<&Deck::outflow_readmits_products>,
           "where the flow turns inward at an outflow side, let the products that left come back (a zero-gradient copy, as before solver revision 9); "
           "default: what enters there is the ambient air (docs/solver.md, Boundaries)"),

      number("mesh", "cell_size_m", in<&Deck::mesh, &MeshSpec::cell_size_m>, "m", {1e-4, 0.1}, "uniform core cell"),
      number("mesh", "grading", in<&Deck::mesh, &MeshSpec::grading>, "-", {1.0, 1.5}, "growth per cell outside the core"),
      number("mesh", "core_radius_m", in<&Deck::mesh, &MeshSpec::core_radius_m>, "m", {0.0, 100.0, true},
             "the uniform core's radius; at least cell_size_m and at most domain_radius_m"),
      number("mesh", "core_bottom_m", in<&Deck::mesh, &MeshSpec::core_bottom_m>, "m", any_length,
             "the uniform core's bottom; its vertical cells are laid from z = 0 (the soil surface is a face at every cell size), so its ends move by under half a cell"),
      number("mesh", "core_top_m", in<&Deck::mesh, &MeshSpec::core_top_m>, "m", any_length, "the uniform core's top; above core_bottom_m"),
      number("mesh", "domain_radius_m", in<&Deck::mesh, &MeshSpec::domain_radius_m>, "m", {0.0, 100.0, true}, "the domain's radius (the side: outflow)"),
      number("mesh", "domain_bottom_m", in<&Deck::mesh, &MeshSpec::domain_bottom_m>, "m", any_length,
             "the domain's bottom (a rigid ground); at most core_bottom_m"),
      number("mesh", "domain_top_m", in<&Deck::mesh, &MeshSpec::domain_top_m>, "m", any_length, "the domain's top (outflow); at least core_top_m"),

      text("soil", "name", layer<&SoilSpec::name>, {}, "the layer's label; one or more [[soil]] tables, stacked top to bottom, the highest at z = 0"),
      number("soil", "wet_density_kg_m3", layer<&SoilSpec::wet_density_kg_m3>, "kg/m3", density,
             "wet (gross) density; give it or dry_density_kg_m3 (the other 0); the sand model bounds it (docs/sand-model.md)"),
      number("soil", "dry_density_kg_m3", layer<&SoilSpec::dry_density_kg_m3>, "kg/m3", density,
             "dry density; porosity at most 0.7 and below the grain density"),
      number("soil", "moisture", layer<&SoilSpec::moisture>, "-", kMoistureRange, "gravimetric (0.07 = 7%); saturation at most 100%"),
      number("soil", "top_m", layer<&SoilSpec::top_m>, "m", any_length, "the layer's top; the highest layer's top is the ground, z = 0"),
      number("soil", "bottom_m", layer<&SoilSpec::bottom_m>, "m", any_length, "the layer's bottom; below top_m, inside the domain"),
      number("soil", "radius_m", layer<&SoilSpec::radius_m>, "m", {0.0, 1e3}, "the layer's radius; 0: the whole width of the domain"),
      text("soil", "water_eos", layer<&SoilSpec::water_eos>, {"awg", "alt"}, "the pore water's Hugoniot set (docs/sand-model.md)"),
      number("soil", "plateau_scale", layer<&SoilSpec::plateau_scale>, "-", kPlateauScaleRange, "multiplier on the effective-stress yield plateau"),
      number("soil", "thermal_gamma", layer<&SoilSpec::thermal_gamma>, "-", kThermalGammaRange,
             "the energy term's Gruneisen coefficient, p = C(x) + gamma T(x) rho0 e; -1: derived from the constituents (docs/solver.md)", -1.0),
      number("soil", "shear_modulus_cap_pa", layer<&SoilSpec::shear_modulus_cap_pa>, "Pa", kShearModulusCapRange,
             "the cap on the skeleton's shear modulus, which grows with the compaction seen; 0: the quartz grains' own, 45 GPa (docs/sand-model.md)", 0.0),
      text("soil", "shear_modulus_law", layer<&SoilSpec::shear_modulus_law>, {"compaction", "pressure"},
           "what the skeleton's shear modulus follows: the largest compaction seen (it stays after unloading) or the effective pressure now "
           "(docs/sand-model.md)"),
      number("soil", "min_poisson_ratio", layer<&SoilSpec::min_poisson_ratio>, "-", kMinPoissonRatioRange,
             fmt::format("the Poisson's ratio that bounds the skeleton's shear modulus on the unloading bulk modulus; default the Sjobo sand's "
                         "measured {:g} (docs/sand-model.md)", materials::kSjoboPoisson)),

      flag("backfill", "enabled", in<&Deck::backfill, &BackfillSpec::enabled>,
           "a dug-and-backfilled cover over the charge, from the surface to the charge top (soil options of the first layer)"),
      number("backfill", "radius_m", in<&Deck::backfill, &BackfillSpec::radius_m>, "m", {0.0, 1e3}, "the backfill's radius; 0: the charge radius + 0.05 m"),
      number("backfill", "wet_density_kg_m3", in<&Deck::backfill, &BackfillSpec::wet_density_kg_m3>, "kg/m3", density,
             "the backfill's wet density; give it or dry_density_kg_m3 when enabled"),
      number("backfill", "dry_density_kg_m3", in<&Deck::backfill, &BackfillSpec::dry_density_kg_m3>, "kg/m3", density, "the backfill's dry density"),
      number("backfill", "moisture", in<&Deck::backfill, &BackfillSpec::moisture>, "-", kMoistureRange, "the backfill's gravimetric moisture; saturation at most 100%"),

      text("charge", "explosive", in<&Deck::charge, &ChargeSpec::explosive>, {"C4", "CompB", "TNT"}, "JWL products (shared/data/explosives_jwl.csv)"),
      number("charge", "mass_kg", in<&Deck::charge, &ChargeSpec::mass_kg>, "kg", {0.0, 1000.0, true}, "the charge's mass"),
      text("charge", "shape", in<&Deck::charge, &ChargeSpec::shape>, {"cylinder", "sphere", "box"}, "box (square in plan) only in 3D"),
      number("charge", "height_to_diameter", in<&Deck::charge, &ChargeSpec::height_to_diameter>, "-", {0.05, 20.0},
             "the cylinder's height over its diameter (box: height over side)"),
      number("charge", "depth_of_burial_m", in<&Deck::charge, &ChargeSpec::depth_of_burial_m>, "m", {0.0, 10.0},
             "soil cover over the charge's top; the charge's top lies inside a soil layer"),
      text("charge", "detonation", in<&Deck::charge, &ChargeSpec::detonation>, {"bottom", "centre", "top"}, "the detonation point, on the axis"),

      flag("early", "enabled", in<&Deck::early, &EarlySpec::enabled>,
           "run the detonation and first expansion on a fine nested block and map it onto the run mesh (docs/solver.md, Early time); "
           "used where the run's cells give fewer than cells_per_charge_height over the charge; a 3D run takes the axisymmetric block onto its quarter (a round charge; the block stays below the target)"),
      number("early", "cells_per_charge_height", in<&Deck::early, &EarlySpec::cells_per_charge_height>, "-", {4.0, 200.0}, "the fine block's resolution"),
      number("early", "map_time_s", in<&Deck::early, &EarlySpec::map_time_s>, "s", {0.0, 1e-3},
             "map no later than this; 0: when the fastest wave could reach the block's edge"),
      number("early", "signal_speed_m_s", in<&Deck::early, &EarlySpec::signal_speed_m_s>, "m/s", {1000.0, 20000.0},
             "the fastest wave the block must hold by the map time"),
      number("early", "block_margin_m", in<&Deck::early, &EarlySpec::block_margin_m>, "m", {0.01, 2.0},
             "the block's reach past the charge (clipped to the uniform core); 0: signal_speed_m_s times four burn times (EMI: 0.21 m)", 0.0),

      number("air", "pressure_pa", top<&Deck::air_pressure_pa>, "Pa", {1.0, 1e7}, "ambient air pressure (ideal gas, gamma 1.4)"),
      number("air", "density_kg_m3", top<&Deck::air_density_kg_m3>, "kg/m3", {1e-3, 100.0}, "ambient air density"),

      text("target", "kind", in<&Deck::target, &TargetSpec::kind>, {"disc", "annulus", "rectangle", "v", "none"},
           "the plate; rectangle and v (ridge along x, keel down) only in 3D"),
      number("target", "radius_m", in<&Deck::target, &TargetSpec::radius_m>, "m", {0.0, 100.0, true}, "disc and annulus: outer radius, at most mesh.domain_radius_m"),
      number("target", "inner_radius_m", in<&Deck::target, &TargetSpec::inner_radius_m>, "m", {0.0, 100.0}, "annulus: inner radius, at most radius_m"),
      number("target", "thickness_m", in<&Deck::target, &TargetSpec::thickness_m>, "m", {0.0, 1.0, true}, "the plate's thickness; at least mesh.cell_size_m"),
      number("target", "standoff_m", in<&Deck::target, &TargetSpec::standoff_m>, "m", {0.0, 100.0},
             "from the soil surface to the plate's underside; the plate lies inside the domain"),
      number("target", "mass_kg", in<&Deck::target, &TargetSpec::mass_kg>, "kg", {0.0, 1e6}, "the plate's mass; > 0 when motion = free"),
      text("target", "motion", in<&Deck::target, &TargetSpec::motion>, {"free", "fixed"}, "free: moves under the load and gravity"),
      flag("target", "move_mesh", in<&Deck::target, &TargetSpec::move_mesh>,
           "a free plate moves through the mesh: the mesh from mesh.core_bottom_m up to the plate stretches with it and the mesh above it "
           "closes up (docs/run.md); false: its cells stay where they started and its velocity enters the wall condition only"),
      number("target", "friction", in<&Deck::target, &TargetSpec::friction>, "-", {0.0, 2.0}, "Coulomb coefficient between the plate and the soil (it acts on the soil's share of the contact; gas, products and water slide freely); the EMI decks use 0.2"),
      number("target", "half_length_m", in<&Deck::target, &TargetSpec::half_length_m>, "m", {0.0, 100.0, true},
             "rectangle and V: half extent along x (the V's ridge), at most mesh.domain_radius_m"),
      number("target", "half_width_m", in<&Deck::target, &TargetSpec::half_width_m>, "m", {0.0, 100.0, true},
             "rectangle and V: half extent along y, at most mesh.domain_radius_m"),
      number("target", "apex_angle_deg", in<&Deck::target, &TargetSpec::apex_angle_deg>, "degrees", {30.0, 180.0}, "V: the angle between its wings (180 = flat)"),

      number("output", "history_interval_s", in<&Deck::output, &OutputSpec::history_interval_s>, "s", {1e-8, 1.0}, "history and gauge sampling"),
      list("output", "profile_times_s", in<&Deck::output, &OutputSpec::profile_times_s>, KeyType::NumberList, "s", {0.0, kInf, true, true},
           "soil-surface profile times, increasing (times past end_time_s are not reached; times within the early time are taken at its map time)"),
      list("output", "field_times_s", in<&Deck::output, &OutputSpec::field_times_s>, KeyType::NumberList, "s", {0.0, kInf, true, true},
           "VTK snapshot times, increasing (times within the early time are taken at its map time, which fields.pvd records)"),
      list("output", "gauges_m", in<&Deck::output, &OutputSpec::gauges_m>, KeyType::PointList, "m", any_length,
           "pressure gauges, a list of [r, z] points inside the domain, in the flow (not in the target)"),
      number("output", "surface_soil_fraction", in<&Deck::output, &OutputSpec::surface_soil_fraction>, "-", {0.01, 1.0},
             "soil volume fraction that marks the soil surface in profiles and histories (DRES decks: 0.1, the envelope a film sees)"),
  };
  Deck defaults;
  defaults.soil.resize(1);
  for (auto& key : k) {
    key.info.path = key.section.empty() ? key.name : (key.section == "soil" ? "soil.N." : key.section + ".") + key.name;
    key.info.default_text = std::visit(
        [](auto* v) -> std::string {
          using T = std::remove_pointer_t<decltype(v)>;
          if constexpr (std::is_same_v<T, double>) return fmt::format("{:.6g}", *v);
          else if constexpr (std::is_same_v<T, std::string>) return fmt::format("\"{}\"", *v);
          else if constexpr (std::is_same_v<T, bool>) return *v ? "true" : "false";
          else if constexpr (std::is_same_v<T, std::vector<double>>) return fmt::format("[{}]", fmt::join(*v, ", "));
          else return v->empty() ? "[]" : "[...]";
        },
        key.field(defaults, 0));
  }
  return k;
}

const std::vector<Key>& keyTable() {
  static const std::vector<Key> keys = makeKeys();
  return keys;
}

std::string keyPath(const Key& k, std::size_t layer_index) {
  if (k.section.empty()) return k.name;
  if (k.section == "soil") return fmt::format("soil.{}.{}", layer_index, k.name);
  return k.section + "." + k.name;
}

const toml::table* sectionTable(const toml::table& root, const std::string& section) {
  const auto* n = root.get(section);
  if (!n) return nullptr;
  if (!n->as_table()) throw InputError(section, fmt::format("must be a table [{}]", section));
  return n->as_table();
}

// Reads one key's TOML value into the deck, by its type.
void readValue(const toml::node& n, FieldRef f, const std::string& path) {
  std::visit(
      [&](auto* v) {
        using T = std::remove_pointer_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) {
          const auto d = n.value<double>();
          if (!d || n.is_boolean()) throw InputError(path, "must be a number");
          *v = *d;
        } else if constexpr (std::is_same_v<T, std::string>) {
          const auto s = n.value<std::string>();
          if (!s) throw InputError(path, "must be a string");
          *v = *s;
        } else if constexpr (std::is_same_v<T, bool>) {
          if (!n.is_boolean()) throw InputError(path, "must be true or false");   // value<bool>() would take 1 as true
          *v = *n.value<bool>();
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          const auto* arr = n.as_array();
          if (!arr) throw InputError(path, "must be a list of numbers");
          v->clear();
          for (const auto& e : *arr) {
            const auto d = e.value<double>();
            if (!d || e.is_boolean()) throw InputError(path, "must be a list of numbers");
            v->push_back(*d);
          }
        } else {
          const auto* arr = n.as_array();
          if (!arr) throw InputError(path, "must be a list of [r, z] pairs (m)");
          v->clear();
          for (const auto& e : *arr) {
            const auto* pt = e.as_array();
            if (!pt || pt->size() != 2 || !(*pt)[0].value<double>() || !(*pt)[1].value<double>() || (*pt)[0].is_boolean() || (*pt)[1].is_boolean())
              throw InputError(path, "must be a list of [r, z] pairs (m)");
            v->push_back({*(*pt)[0].value<double>(), *(*pt)[1].value<double>()});
          }
        }
      },
      f);
}

// The key's own range and choices.
void checkValue(const Key& k, FieldRef f, const std::string& path) {
  const auto& info = k.info;
  std::visit(
      [&](auto* v) {
        using T = std::remove_pointer_t<decltype(v)>;
        if constexpr (std::is_same_v<T, double>) {
          if (info.special && *v == *info.special) return;
          if (!std::isfinite(*v)) throw InputError(path, "must be a finite number");
          if (!info.range.contains(*v))
            throw InputError(path, fmt::format("{:g} {} is out of range; valid {} {}{}", *v, info.unit, info.range.text(), info.unit,
                                               info.special ? fmt::format(" (or {:g})", *info.special) : std::string()));
        } else if constexpr (std::is_same_v<T, std::string>) {
          if (info.choices.empty() || std::find(info.choices.begin(), info.choices.end(), *v) != info.choices.end()) return;
          throw InputError(path, fmt::format("'{}' is not valid; valid: {}", *v, fmt::join(info.choices, ", ")));
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          for (const double x : *v)
            if (!std::isfinite(x) || !info.range.contains(x))
              throw InputError(path, fmt::format("{:g} {} is out of range; valid {} {}", x, info.unit, info.range.text(), info.unit));
        } else if constexpr (std::is_same_v<T, std::vector<std::vector<double>>>) {
          for (const auto& p : *v)
            for (const double x : p)
              if (!std::isfinite(x) || !info.range.contains(x))
                throw InputError(path, fmt::format("{:g} {} is out of range; valid {} {}", x, info.unit, info.range.text(), info.unit));
        }
      },
      f);
}

nlohmann::json jsonOf(FieldRef f) {
  return std::visit([](auto* v) { return nlohmann::json(*v); }, f);
}

// A --set value is one TOML value: "v = VALUE" must parse to exactly the one key (text after the
// value, such as a second line, is refused rather than ignored); a bare word is a string.
toml::node_view<toml::node> parsedValue(toml::table& parsed, const std::string& path, const std::string& value) {
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    try {
      parsed = toml::parse("v = \"" + value + "\"");
    } catch (const toml::parse_error&) {
      throw InputError(path, fmt::format("'{}' is not a valid value", value));
    }
  }
  if (parsed.size() != 1) throw InputError(path, fmt::format("'{}' is not one value", value));
  return parsed["v"];
}

void applyOverride(toml::table& root, const std::string& ov) {
  const auto eq = ov.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--set", fmt::format("'{}' is not KEY=VALUE", ov));
  // "key = value" as TOML writes it: the spaces around the key are not part of it
  std::string path = ov.substr(0, eq), value = ov.substr(eq + 1);
  for (auto* text : {&path, &value}) {
    text->erase(0, text->find_first_not_of(" \t"));
    text->erase(text->find_last_not_of(" \t") + 1);
  }
  if (path.empty()) throw InputError("--set", fmt::format("'{}' is not KEY=VALUE", ov));
  toml::table parsed;
  const auto v = parsedValue(parsed, path, value);
  toml::table* t = &root;
  std::size_t start = 0;
  for (;;) {
    const auto dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw InputError(path, "is not a dotted key (KEY or TABLE.KEY)");
    if (dot == std::string::npos) {
      t->insert_or_assign(part, *v.node());
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

// Refuses a key the table does not declare (a section's keys, or the top level's).
void refuseUnknownKeys(const toml::table& t, const std::string& section, const std::string& prefix) {
  const auto& keys = keyTable();
  for (const auto& [name, node] : t) {
    const std::string n(name.str());
    const bool declared = std::any_of(keys.begin(), keys.end(), [&](const Key& k) { return k.section == section && k.name == n; });
    if (declared) continue;
    const bool is_section = section.empty() && std::any_of(keys.begin(), keys.end(), [&](const Key& k) { return k.section == n; });
    if (!is_section) throw InputError(prefix.empty() ? n : prefix + "." + n, "unknown key");
  }
}

// The sand model checks what only it can (porosity, saturation at most 100%, grains that leave
// voids); its errors name its own inputs, which are renamed here to the deck's keys.
void checkSand(const materials::SandInputs& in, const std::string& prefix, bool wet_given) {
  try {
    materials::SandModel model(in);
  } catch (const InputError& e) {
    const std::string& f = e.field();
    std::string msg = e.what();
    if (msg.rfind(f + ": ", 0) == 0) msg = msg.substr(f.size() + 2);
    std::string key = f;
    if (f == "dry-density" || f == "wet-density") {
      key = wet_given ? "wet_density_kg_m3" : "dry_density_kg_m3";
      if (wet_given) msg += " (the dry density, wet_density_kg_m3 / (1 + moisture))";
    } else {
      static const std::map<std::string, std::string> deck_key{
          {"plateau-scale", "plateau_scale"}, {"thermal-gamma", "thermal_gamma"}, {"shear-modulus-cap", "shear_modulus_cap_pa"},
          {"min-poisson-ratio", "min_poisson_ratio"}};
      if (const auto it = deck_key.find(f); it != deck_key.end()) key = it->second;
    }
    throw InputError(prefix + "." + key, msg);
  }
}

// Ranges that depend on other keys, and the geometry meaning what the deck says.
void checkConsistency(const Deck& d) {
  const auto& m = d.mesh;
  if (!(m.core_radius_m >= m.cell_size_m && m.core_radius_m <= m.domain_radius_m))
    throw InputError("mesh.core_radius_m", fmt::format("{:g} m is out of range; valid [mesh.cell_size_m, mesh.domain_radius_m] = [{:g}, {:g}] m", m.core_radius_m,
                                                       m.cell_size_m, m.domain_radius_m));
  if (!(m.domain_bottom_m <= m.core_bottom_m && m.core_bottom_m < m.core_top_m && m.core_top_m <= m.domain_top_m))
    throw InputError("mesh.core_bottom_m", "need domain_bottom_m <= core_bottom_m < core_top_m <= domain_top_m");
  if (d.soil.empty()) throw InputError("soil", "at least one [[soil]] layer is needed");
  for (std::size_t i = 0; i < d.soil.size(); ++i) {
    const auto& s = d.soil[i];
    const std::string key = fmt::format("soil.{}", i);
    if ((s.wet_density_kg_m3 > 0.0) == (s.dry_density_kg_m3 > 0.0))
      throw InputError(key, "give exactly one of wet_density_kg_m3 and dry_density_kg_m3 (> 0)");
    if (!(s.top_m > s.bottom_m)) throw InputError(key + ".top_m", "must be above bottom_m");
    checkSand(sandInputsOf(s), key, s.wet_density_kg_m3 > 0.0);
  }
  const auto& b = d.backfill;
  if (b.enabled) {
    if ((b.wet_density_kg_m3 > 0.0) == (b.dry_density_kg_m3 > 0.0))
      throw InputError("backfill", "give exactly one of wet_density_kg_m3 and dry_density_kg_m3 (> 0)");
    checkSand(sandInputsOf(b, d.soil[0]), "backfill", b.wet_density_kg_m3 > 0.0);
  }
  const bool three_d = d.geometry == "3d-quarter";
  if (d.charge.shape == "box" && !three_d)
    throw InputError("charge.shape", "'box' needs geometry = \"3d-quarter\" (2D axisymmetric: cylinder or sphere)");
  const auto& t = d.target;
  if ((t.kind == "rectangle" || t.kind == "v") && !three_d)
    throw InputError("target.kind", fmt::format("'{}' needs geometry = \"3d-quarter\" (2D axisymmetric: disc or annulus)", t.kind));
  auto within = [](const std::string& key, double v, double lo, double hi, const std::string& bounds) {
    if (!(v >= lo && v <= hi)) throw InputError(key, fmt::format("{:g} m is out of range; valid {} = [{:g}, {:g}] m", v, bounds, lo, hi));
  };
  // each kind's own extents (the others' defaults do not apply to it)
  if (t.kind == "rectangle" || t.kind == "v") {
    within("target.half_length_m", t.half_length_m, 0.0, m.domain_radius_m, "(0, mesh.domain_radius_m]");
    within("target.half_width_m", t.half_width_m, 0.0, m.domain_radius_m, "(0, mesh.domain_radius_m]");
  }
  if (t.kind == "disc" || t.kind == "annulus") {
    within("target.radius_m", t.radius_m, 0.0, m.domain_radius_m, "(0, mesh.domain_radius_m]");
    within("target.inner_radius_m", t.inner_radius_m, 0.0, t.radius_m, "[0, target.radius_m]");
  }
  if (t.kind != "none") {
    within("target.thickness_m", t.thickness_m, m.cell_size_m, 1.0, "[mesh.cell_size_m, 1]");
    within("target.standoff_m", t.standoff_m, 0.0, m.domain_top_m, "[0, mesh.domain_top_m]");
    if (t.motion == "free" && !(t.mass_kg > 0.0))
      throw InputError("target.mass_kg", fmt::format("{:g} kg is out of range; a free target needs a mass in (0, 1e+06] kg", t.mass_kg));
    if (t.standoff_m + t.thickness_m > m.domain_top_m - 2.0 * m.cell_size_m)
      throw InputError("target.standoff_m", "the plate must lie inside the domain (raise mesh.domain_top_m)");
  }
  const auto& out = d.output;
  // output times: increasing (times after end_time_s are simply not reached: a run shortened with
  // --set end_time_s keeps its deck's later times)
  for (const auto& [key, times] : {std::pair<const char*, const std::vector<double>*>{"output.profile_times_s", &out.profile_times_s},
                                   {"output.field_times_s", &out.field_times_s}}) {
    double prev = 0.0;
    for (const double time : *times) {
      if (!(time > prev)) throw InputError(key, fmt::format("{:g} s is out of range; valid: increasing times > 0 s", time));
      prev = time;
    }
  }
  for (const auto& g : out.gauges_m) {
    if (g[0] < 0.0 || g[0] > m.domain_radius_m || g[1] < m.domain_bottom_m || g[1] > m.domain_top_m)
      throw InputError("output.gauges_m", fmt::format("gauge ({:g}, {:g}) m is outside the domain", g[0], g[1]));
  }

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
}

std::string typeName(const DeckKeyInfo& k) {
  switch (k.type) {
    case KeyType::Number: return "number";
    case KeyType::Text: return "text";
    case KeyType::Boolean: return "boolean";
    case KeyType::NumberList: return "list of numbers";
    case KeyType::PointList: return "list of [r, z]";
  }
  return "";
}

std::string validText(const DeckKeyInfo& k) {
  if (k.type == KeyType::Boolean) return "true, false";
  if (k.type == KeyType::Text) return k.choices.empty() ? "any" : fmt::format("{}", fmt::join(k.choices, ", "));
  std::string r = k.range.text();
  if (k.special) r += fmt::format(" or {:g}", *k.special);
  return r;
}

}  // namespace

const std::vector<DeckKeyInfo>& deckKeys() {
  static const std::vector<DeckKeyInfo> infos = [] {
    std::vector<DeckKeyInfo> v;
    for (const auto& k : keyTable()) v.push_back(k.info);
    return v;
  }();
  return infos;
}

std::string deckReference(bool markdown) {
  std::string out;
  if (markdown) {
    out += "| key | type | unit | valid | default | meaning |\n|---|---|---|---|---|---|\n";
    for (const auto& k : deckKeys())
      out += fmt::format("| `{}` | {} | {} | {} | `{}` | {} |\n", k.path, typeName(k), k.unit.empty() ? "" : k.unit, validText(k), k.default_text, k.help);
    return out;
  }
  for (const auto& k : deckKeys())
    out += fmt::format("{}  ({}{}; valid {}; default {})\n    {}\n", k.path, typeName(k), k.unit.empty() ? "" : ", " + k.unit, validText(k),
                       k.default_text, k.help);
  return out;
}

materials::SandInputs sandInputsOf(const SoilSpec& s) {
  materials::SandInputs in;
  in.moisture = s.moisture;
  in.dry_density = s.wet_density_kg_m3 > 0.0 ? s.wet_density_kg_m3 / (1.0 + s.moisture) : s.dry_density_kg_m3;
  in.water = materials::waterEosByName(s.water_eos);
  in.plateau.scale = s.plateau_scale;
  in.thermal_gamma = s.thermal_gamma;
  in.shear_modulus_cap = s.shear_modulus_cap_pa;
  in.shear_follows_pressure = s.shear_modulus_law == "pressure";
  in.min_poisson_ratio = s.min_poisson_ratio;
  return in;
}

materials::SandInputs sandInputsOf(const BackfillSpec& b, const SoilSpec& first_layer) {
  SoilSpec s = first_layer;
  s.wet_density_kg_m3 = b.wet_density_kg_m3;
  s.dry_density_kg_m3 = b.dry_density_kg_m3;
  s.moisture = b.moisture;
  return sandInputsOf(s);
}

Deck parseDeck(const std::string& text, const std::vector<std::string>& overrides, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw InputError(source, fmt::format("TOML syntax error at line {}: {}", e.source().begin.line, e.description()));
  }
  for (const auto& ov : overrides) applyOverride(root, ov);

  // the shape of the file: known keys only, tables where the table has sections
  refuseUnknownKeys(root, "", "");
  std::vector<const toml::table*> layers;
  if (const auto* n = root.get("soil")) {
    const auto* arr = n->as_array();
    if (!arr) throw InputError("soil", "must be [[soil]] tables");
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const auto* t = arr->get(i)->as_table();
      if (!t) throw InputError("soil", "must be [[soil]] tables");
      refuseUnknownKeys(*t, "soil", fmt::format("soil.{}", i));
      layers.push_back(t);
    }
  }
  std::set<std::string> sections;
  for (const auto& k : keyTable())
    if (!k.section.empty() && k.section != "soil") sections.insert(k.section);
  for (const auto& s : sections)
    if (const auto* t = sectionTable(root, s)) refuseUnknownKeys(*t, s, s);

  Deck d;
  d.soil.resize(layers.size());
  for (const auto& k : keyTable()) {
    const std::size_t n = k.section == "soil" ? layers.size() : 1;
    for (std::size_t i = 0; i < n; ++i) {
      const toml::table* t = k.section.empty() ? &root : (k.section == "soil" ? layers[i] : sectionTable(root, k.section));
      if (!t) continue;
      const std::string path = keyPath(k, i);
      if (const auto* node = t->get(k.name)) readValue(*node, k.field(d, i), path);
    }
  }
  // every key's own range, defaults included, then what depends on other keys
  for (const auto& k : keyTable()) {
    const std::size_t n = k.section == "soil" ? d.soil.size() : 1;
    for (std::size_t i = 0; i < n; ++i) checkValue(k, k.field(d, i), keyPath(k, i));
  }
  checkConsistency(d);

  // the resolved deck: every key's value, so that a changed default shows in the echo
  nlohmann::json echo = nlohmann::json::object();
  echo["soil"] = nlohmann::json::array();
  for (std::size_t i = 0; i < d.soil.size(); ++i) echo["soil"].push_back(nlohmann::json::object());
  for (const auto& k : keyTable()) {
    if (k.section == "soil") {
      for (std::size_t i = 0; i < d.soil.size(); ++i) echo["soil"][i][k.name] = jsonOf(k.field(d, i));
    } else if (k.section.empty()) {
      echo[k.name] = jsonOf(k.field(d, 0));
    } else {
      echo[k.section][k.name] = jsonOf(k.field(d, 0));
    }
  }
  d.echo = std::move(echo);
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
