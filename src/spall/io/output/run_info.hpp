#pragma once
// run.json: what a run was (version, threads, ranks, deck) and how it went (steps, wall time,
// the time spent in each phase of the step).
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace spall::io::output {

struct RunInfo {
  std::string version;
  std::string deck;
  int threads = 1;
  int ranks = 1;
  long long rebalances = 0;  // under MPI: how often the nodes were dealt anew (solver::LoadBalance)
  // Under MPI, which velocities travel each step: "by reach" (those the formulations read, and the
  // rigid bodies' nodes' forces) or "every node"; "one process" otherwise.
  std::string halo = "one process";
  // Under MPI: the bytes a rank received from the others a step (Communicator::received_bytes), the
  // mean and the largest over the ranks; 0 for one process.
  double received_bytes_mean = 0;
  double received_bytes_max = 0;
  // Under MPI: a rank's seconds inside the collectives (Communicator::communicating_seconds:
  // waiting for the other ranks included), the mean and the largest over the ranks; 0 for one
  // process.
  double communicating_seconds_mean = 0;
  double communicating_seconds_max = 0;
  // The node rows a rank holds at the end (NodeStore::size: every node, unless a rank keeps only
  // those near its region), the mean and the largest over the ranks.
  double node_rows_mean = 0;
  long long node_rows_max = 0;
  // The largest resident set of a rank's process over the run, set-up included
  // (memory::peak_resident_bytes), the mean and the largest over the ranks.
  double peak_resident_bytes_mean = 0;
  long long peak_resident_bytes_max = 0;
  long long steps = 0;
  double end_time = 0;
  double wall_seconds = 0;
  long long nodes = 0;  // nodes with mass: particles and the nodes of elements
  double initial_mass = 0;  // of the nodes, before mass scaling
  std::vector<std::pair<std::string, double>> masses;  // at the last glstat row: eroded_mass, added_mass, ...
  // glstat's last energy ratio; NaN (null in the file) for a model at rest or a run that did not complete.
  double energy_ratio = std::numeric_limits<double>::quiet_NaN();
  std::string status;  // "completed", "unstable", ...
  std::vector<std::pair<std::string, double>> phases;  // seconds spent in each phase of the step
};

void write_run_json(const std::filesystem::path& path, const RunInfo& info);

}  // namespace spall::io::output
