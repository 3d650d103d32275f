// Case expansion: an experiment's datasets x inputs x methods x the
// cartesian product of every swept parameter, each a Case with its id (a
// hash of the fully resolved configuration: what resume, sharding and the
// results directory's identity key on).
#pragma once

#include "orchestration/spec.h"
#include "registry/registry.h"

#include <cstdint>
#include <string>
#include <vector>

namespace arcs {

// A fully resolved unit of work.
struct Case {
  std::string id;        // 16 hex digits, hash of the resolved configuration (CaseKey)
  std::string dataset;
  std::string item;      // the item's name: file stem or built-in name
  DatasetItem source;    // what the case loads
  NormalizeSpec normalize;
  std::string reference_path;  // points datasets: the reference mesh, if any
  std::string input;     // input pipeline name
  std::vector<StageSpec> input_stages;
  std::string method;
  std::vector<StageSpec> method_stages;
  std::vector<StageSpec> metric_stages;
  std::uint64_t seed = 1;  // the experiment's seed
  bool shared_method_seed = false;  // Experiment::shared_method_seed
  // What the method's random stream hashes into the case group's seed: the
  // method's name, or one fixed key when the methods share their stream.
  std::string MethodSeedKey() const { return shared_method_seed ? std::string("method") : method; }
  // Resolved parameters as results columns ("stage.param" -> text), in order.
  std::vector<std::pair<std::string, std::string>> params;
  // Parameter columns that vary across the experiment's cases (for labels).
  std::vector<std::string> varying;
  // Labels' short forms of varying nested-stage values: the stage and only
  // the nested parameters that vary across the cases ("screened_poisson(
  // point_weight=4)" for the whole resolved call), by column.
  std::vector<std::pair<std::string, std::string>> shown;
  // Short human label: "bunny n=20 | grid | MC".
  std::string Label() const;
};

// Expands datasets x inputs x methods x the cartesian product of every
// swept parameter. Deterministic order. Throws ExperimentError for a sweep
// value listed twice, a case that appears twice, or more cases than
// $ARCS_MAX_CASES (default 100 000).
std::vector<Case> ExpandCases(const Experiment& exp, const Registry& registry);

// The text a case's id hashes: the item's key, its dataset's normalisation
// (and reference, for points), both pipelines' resolved stages, the metrics
// and the seed. The id is Hex16(Fnv1a64(CaseKey(...))).
std::string CaseKey(const Case& c, const DatasetSpec& ds, const std::string& metric_key);
// Stages with their resolved parameters, canonically: "a(k=v;...)b(...)".
std::string CanonicalStages(const std::vector<StageSpec>& stages);

}  // namespace arcs
