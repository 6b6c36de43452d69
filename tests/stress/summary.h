#pragma once
// Outcome records of the stress harness (stress_csg.cpp): one per scene and stage, kept as tab-
// separated lines (seed, stage, kind, seconds, detail, scene) so that runs split over several
// processes can be summarized together.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace cover::stress {

struct Record {
  uint64_t seed = 0;
  std::string stage;  ///< oracle, evaluate, cells-N, decompose
  std::string kind;   ///< checks.h "Kinds of outcome"
  double seconds = 0;
  std::string detail;
  std::string scene;  ///< RandomScene::description
};

/// One line (with its newline).
std::string format_record(const Record& r);
/// The records of a results file (lines that do not parse are skipped).
std::vector<Record> read_records(const std::filesystem::path& path);

/// The report: scenes and time, a table of counts per stage and kind, the seeds of every kind
/// that is not ok, and the distinct refusal reasons (digits folded) with their counts. `label`
/// (e.g. the commit) and the UTC date head it.
std::string summary(const std::vector<Record>& records, const std::string& label);

/// True when every record is ok, refused, unavailable or skipped after one of those.
bool passed(const std::vector<Record>& records);

}  // namespace cover::stress
