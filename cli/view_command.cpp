// `cover view` (docs/viewer.md): serves the viewer until interrupted (Ctrl-C or SIGTERM).
#include <csignal>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cover/cli/commands.h"
#include "cover/view/viewer.h"

namespace cover::cli {

int run_view(const ViewCommandOptions& o, const CommonOptions& common) {
  // The signals are blocked before the viewer starts its threads (they inherit the mask), so
  // that this thread alone takes them, by sigwait.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  ViewerOptions vo;
  vo.host = o.host;
  vo.port = o.port;
  vo.poll_seconds = o.poll;
  vo.load = common.load_options();
  vo.max_memory_bytes = common.max_memory_bytes();
  Viewer viewer(o.input, vo);
  for (const std::string& w : viewer.warnings(flag_of))
    std::fprintf(stderr, "cover: warning: %s\n", w.c_str());
  if (common.json) {
    nlohmann::json j;
    j["url"] = viewer.url();
    j["port"] = viewer.port();
    std::printf("%s\n", j.dump().c_str());
  } else {
    std::printf("cover view: %s (Ctrl-C stops)\n", viewer.url().c_str());
  }
  std::fflush(stdout);
  int received = 0;
  sigwait(&signals, &received);
  viewer.stop();
  return 0;
}

}  // namespace cover::cli
