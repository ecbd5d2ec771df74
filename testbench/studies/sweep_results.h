// A sweep's output directory: manifest.json (everything a point needs, so a cluster task or a
// resume runs the same point), DIR/points/pNNNN/ per point, whose row.json is written last and so
// marks the point finished, and results.csv/results.json gathered from the rows present.
#pragma once

#include "testbench/studies/sweep_file.h"

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim {

std::string sweep_manifest_file(const std::string& dir);  // DIR/manifest.json
nlohmann::json sweep_manifest(const SweepSpec& spec);
// The spec a manifest describes; `path` names the manifest in errors.
SweepSpec spec_from_manifest(const nlohmann::json& manifest, const std::string& path);
// The manifest in `dir` must describe the same points (a resume), or be absent (a new sweep: it is
// written). An InputError otherwise, so two sweeps never mix their rows.
void claim_sweep_directory(const SweepSpec& spec, const std::string& dir);
// An InputError naming the first input file (hardware or scene) whose contents differ from when
// the manifest was written: a point run now would not be comparable with the others.
void check_sweep_inputs(const nlohmann::json& manifest, const std::string& dir);

std::string sweep_point_dir(const std::string& dir, const SweepPoint& p);
std::string sweep_row_file(const std::string& dir, const SweepPoint& p);
bool sweep_point_done(const std::string& dir, const SweepPoint& p);
// Why a point has no usable row: "no row", or what is wrong with the one there; "" if it is fine.
std::string sweep_row_problem(const std::string& dir, const SweepPoint& p);
// Where a failed point's reason and log tail are kept until it succeeds.
std::string sweep_failure_file(const std::string& dir, const SweepPoint& p);

// One row of results: the point, its scene's name, its column values and its metrics, from the
// point's report.json.
nlohmann::json sweep_row(const SweepSpec& spec, const SweepPoint& point,
                         const nlohmann::json& report);

// Writes results.csv and results.json from every point's row.json present, and lists the failed
// points (results.json's "failed"; in results.csv a row with the reason in `failure`); returns
// the number of rows present.
size_t write_sweep_results(const SweepSpec& spec, const std::string& dir);

// The Markdown reports the sweep's `reports:` name, beside results.json (area: area_lights.md,
// reports/area_report.h), written whatever --no-plots says; empty on success, else why one was not.
std::string write_sweep_reports(const SweepSpec& spec, const std::string& dir);

// The sweep's figures (plots/) and then its reports' figures (`reports:`), by reports/plots.py;
// empty on success, else why they were not all written.
std::string draw_sweep_figures(const SweepSpec& spec, const std::string& dir);

}  // namespace rtsim
