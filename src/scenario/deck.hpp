#pragma once
// The input deck of `ejecta run`: a TOML file (toml++) describing one buried-charge case. Every
// field's unit is in its name (_m, _kg, _s, _kg_m3, _pa); unknown keys and out-of-range values
// are InputErrors naming the key. `--set key=value` overrides any field before validation.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/range.hpp"
#include "materials/sand_model.hpp"

namespace ejecta::scenario {

struct MeshSpec {
  double cell_size_m = 0.01;
  double grading = 1.05;          // - growth of the cells outside the uniform core
  double core_radius_m = 0.55;    // uniform core r in [0, core_radius]
  double core_bottom_m = -0.25, core_top_m = 0.15;
  double domain_radius_m = 1.2;
  double domain_bottom_m = -0.85, domain_top_m = 0.8;
};

struct SoilSpec {
  std::string name = "sand";
  double wet_density_kg_m3 = 0.0;   // give wet or dry
  double dry_density_kg_m3 = 0.0;
  double moisture = 0.07;           // - gravimetric
  double top_m = 0.0, bottom_m = -0.85;
  double radius_m = 0.0;            // 0: the whole width of the domain
  std::string water_eos = "awg";
  double plateau_scale = 1.0;
  double thermal_gamma = -1.0;        // - the energy term's Gruneisen coefficient; < 0: from the constituents
  double shear_modulus_cap_pa = 0.0;  // Pa, the cap on the skeleton's shear modulus; 0: quartz's
  std::string shear_modulus_law = "pressure";   // what G follows: "compaction" (the largest seen) or "pressure" (now)
  double min_poisson_ratio = materials::kSjoboPoisson;   // -, G <= 3 K_u (1 - 2 nu) / (2 (1 + nu))
};

struct ChargeSpec {
  std::string explosive = "CompB";
  double mass_kg = 0.674;
  std::string shape = "cylinder";     // cylinder (disc), sphere; box (3D: square plan, side a, height k a)
  double height_to_diameter = 1.0 / 3.0;
  double depth_of_burial_m = 0.05;    // soil cover over the top of the charge
  std::string detonation = "bottom";  // bottom, centre, top (on the axis)
};

struct BackfillSpec {
  bool enabled = false;
  double radius_m = 0.0;              // 0: the charge radius + 0.05 m
  double wet_density_kg_m3 = 0.0, dry_density_kg_m3 = 0.0, moisture = 0.07;
};

struct TargetSpec {
  std::string kind = "disc";          // disc, annulus (2D and 3D); rectangle, v (3D); none
  double radius_m = 0.451, inner_radius_m = 0.0;
  double thickness_m = 0.06;
  double standoff_m = 0.0;            // from the soil surface to the plate's underside
  double mass_kg = 300.0;
  std::string motion = "free";        // free (load and gravity) or fixed
  bool move_mesh = true;              // free: the plate moves through the mesh (ALE); false: its cells stay put
  double friction = 0.0;              // - Coulomb coefficient, plate against soil (gas slides freely)
  double half_length_m = 0.4;         // rectangle and V: half extent along x (the V's ridge), m
  double half_width_m = 0.4;          // rectangle and V: half extent along y, m
  double apex_angle_deg = 120.0;      // V: angle between its two wings (180 = flat), degrees
};

// The early-time detonation on a fine mesh (a nested block around the charge), mapped onto the
// run's mesh conservatively per material before any wave leaves the block (hydro/rezone.hpp).
struct EarlySpec {
  bool enabled = true;                   // used where the run's cells are coarser than the charge needs
  double cells_per_charge_height = 20.0; // - the fine block's resolution
  double map_time_s = 0.0;               // s; 0: as late as the block allows
  double signal_speed_m_s = 6000.0;      // m/s, the fastest wave the block must hold by the map time
  double block_margin_m = 0.0;           // m, the block's reach past the charge (clipped to the uniform core);
                                         // 0: the signal speed times four burn times (EMI: 0.21 m)
};

struct OutputSpec {
  double history_interval_s = 1e-5;
  std::vector<double> profile_times_s{0.5e-3, 1e-3, 2e-3, 4e-3};
  std::vector<double> field_times_s{1e-3, 5e-3};
  std::vector<std::vector<double>> gauges_m;   // [r, z] points
  // A column's soil surface is the top of its highest cell holding at least this volume fraction
  // of soil. 0.5 tracks the bulk surface; a film of a soil bubble sees the envelope of the cloud,
  // closer to a small fraction (the DRES decks use 0.1).
  double surface_soil_fraction = 0.5;
};

struct Deck {
  std::string title = "ejecta case";
  std::string geometry = "axisymmetric";   // or "3d-quarter": x, y >= 0 symmetry planes, z up
  MeshSpec mesh;
  std::vector<SoilSpec> soil;
  BackfillSpec backfill;
  ChargeSpec charge;
  double air_pressure_pa = 101325.0, air_density_kg_m3 = 1.225;
  TargetSpec target;
  bool gravity = true;
  double end_time_s = 0.01;
  double cfl = 0.30;
  double fragment_fold = 1e-10;
  bool outflow_readmits_products = false;
  std::string mixture_stiffness = "reuss";
  std::string interface_remap = "thinc";
  EarlySpec early;
  OutputSpec output;
  nlohmann::json echo;   // the resolved deck: every key's value after the file, --set and the defaults
};

// --- the deck's keys, declared once -------------------------------------------------------------
// One table drives the TOML reader, `--set`, the range checks, `ejecta run --help-deck`, the deck
// reference in docs/run.md (generated from it, with a test that it is current) and the resolved
// deck echoed in summary.json. A key's default is the Spec struct's initialiser above.
enum class KeyType { Number, Text, Boolean, NumberList, PointList };

struct DeckKeyInfo {
  std::string path;                    // dotted, as --set takes it; layers: "soil.N.moisture"
  KeyType type = KeyType::Number;
  std::string unit;                    // SI unit ("-" for a ratio), empty for text and booleans
  Range range;                         // numbers (and each number of a list)
  std::optional<double> special;       // a value allowed outside the range, with its meaning in help
  std::vector<std::string> choices;    // text keys with a fixed set of values; empty: free text
  std::string help;
  std::string default_text;            // the default, as a TOML value
};
const std::vector<DeckKeyInfo>& deckKeys();
// The reference table for docs/run.md (markdown) and for `--help-deck` (plain text).
std::string deckReference(bool markdown);

// The sand model's inputs of a layer and of the backfill (which takes the first layer's options).
materials::SandInputs sandInputsOf(const SoilSpec& s);
materials::SandInputs sandInputsOf(const BackfillSpec& b, const SoilSpec& first_layer);

// Parses TOML text; `overrides` are "dotted.key=value" with a TOML value. Throws InputError.
Deck parseDeck(const std::string& text, const std::vector<std::string>& overrides = {}, const std::string& source = "deck");
Deck loadDeck(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace ejecta::scenario
