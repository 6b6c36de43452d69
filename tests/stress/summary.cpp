#include "summary.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace cover::stress {
namespace {

const std::vector<std::string> kKinds = {
    "ok",         "refused",  "unavailable", "bad-input", "internal", "memory",  "invalid",
    "degenerate", "touching", "not-convex",  "volume",    "crash",    "timeout", "skipped"};

/// Stage order: oracle, evaluate, cells by N, decompose.
int stage_rank(const std::string& s) {
  if (s == "oracle") return 0;
  if (s == "evaluate") return 1;
  if (s == "decompose") return 1 << 20;
  if (s.rfind("cells-", 0) == 0) return 2 + std::atoi(s.c_str() + 6);
  return 1 << 21;
}

/// The reason with every run of digits (and a following ".digits", "e-digits") folded to '#'.
std::string fold(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size();) {
    if (std::isdigit(static_cast<unsigned char>(s[i]))) {
      while (i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.' ||
                              s[i] == 'e' || s[i] == '-' || s[i] == '+'))
        ++i;
      out += '#';
    } else {
      out += s[i++];
    }
  }
  return out.size() > 150 ? out.substr(0, 150) + "..." : out;
}

}  // namespace

std::string format_record(const Record& r) {
  char secs[32];
  std::snprintf(secs, sizeof secs, "%.3f", r.seconds);
  return std::to_string(r.seed) + "\t" + r.stage + "\t" + r.kind + "\t" + secs + "\t" + r.detail +
         "\t" + r.scene + "\n";
}

std::vector<Record> read_records(const std::filesystem::path& path) {
  std::vector<Record> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::istringstream s(line);
    for (std::string x; std::getline(s, x, '\t');) f.push_back(x);
    if (f.size() < 4) continue;
    try {
      out.push_back({std::stoull(f[0]), f[1], f[2], std::stod(f[3]), f.size() > 4 ? f[4] : "",
                     f.size() > 5 ? f[5] : ""});
    } catch (const std::exception&) {
    }
  }
  return out;
}

std::string summary(const std::vector<Record>& records, const std::string& label) {
  std::set<uint64_t> seeds;
  std::map<std::string, std::map<std::string, int>> counts;
  std::map<std::string, double> seconds;
  std::map<std::pair<std::string, std::string>, std::vector<uint64_t>> failing;
  std::map<std::string, int> reasons;
  std::set<std::string> kinds_seen;
  for (const Record& r : records) {
    seeds.insert(r.seed);
    ++counts[r.stage][r.kind];
    seconds[r.stage] += r.seconds;
    kinds_seen.insert(r.kind);
    if (r.kind != "ok") failing[{r.stage, r.kind}].push_back(r.seed);
    if (r.kind == "refused" || r.kind == "bad-input" || r.kind == "internal" ||
        r.kind == "unavailable")
      ++reasons[r.stage.substr(0, r.stage.find('-')) + " " + r.kind + ": " + fold(r.detail)];
  }
  std::vector<std::string> stages;
  for (const auto& [s, c] : counts) stages.push_back(s);
  std::sort(stages.begin(), stages.end(), [](const std::string& a, const std::string& b) {
    return stage_rank(a) < stage_rank(b);
  });
  std::vector<std::string> kinds;
  for (const std::string& k : kKinds)
    if (kinds_seen.count(k)) kinds.push_back(k);
  for (const std::string& k : kinds_seen)
    if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) kinds.push_back(k);

  std::ostringstream out;
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  out << "random-CSG stress: " << seeds.size() << " scenes";
  if (!seeds.empty()) out << " (seeds " << *seeds.begin() << " to " << *seeds.rbegin() << ")";
  out << ", " << date << (label.empty() ? "" : ", " + label) << "\n\n";
  out << "| stage | seconds |";
  for (const std::string& k : kinds) out << " " << k << " |";
  out << "\n|---|---:|";
  for (size_t i = 0; i < kinds.size(); ++i) out << "---:|";
  out << "\n";
  for (const std::string& s : stages) {
    char secs[32];
    std::snprintf(secs, sizeof secs, "%.0f", seconds[s]);
    out << "| " << s << " | " << secs << " |";
    for (const std::string& k : kinds) out << " " << counts[s][k] << " |";
    out << "\n";
  }
  if (!failing.empty()) out << "\nseeds per stage and kind (not ok):\n";
  std::vector<std::pair<std::string, std::string>> keys;
  for (const auto& [k, v] : failing) keys.push_back(k);
  std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
    return stage_rank(a.first) != stage_rank(b.first) ? stage_rank(a.first) < stage_rank(b.first)
                                                      : a.second < b.second;
  });
  for (const auto& k : keys) {
    std::vector<uint64_t>& v = failing[k];
    std::sort(v.begin(), v.end());
    out << "  " << k.first << " " << k.second << " (" << v.size() << "):";
    for (uint64_t s : v) out << " " << s;
    out << "\n";
  }
  if (!reasons.empty()) out << "\nreasons (digits folded to #), count:\n";
  for (const auto& [r, n] : reasons) out << "  " << n << "  " << r << "\n";
  return out.str();
}

bool passed(const std::vector<Record>& records) {
  for (const Record& r : records)
    if (r.kind != "ok" && r.kind != "refused" && r.kind != "unavailable" && r.kind != "skipped")
      return false;
  return true;
}

}  // namespace cover::stress
