#include "cover/solid/errors.h"

namespace cover {
namespace {
// A parameter's name travels between two unit separators (U+001F), which no message text holds
// (messages show control bytes of user text as '?').
constexpr char kMark = '\x1f';

std::string render(std::string_view marked,
                   const std::function<std::string(std::string_view)>& name_of) {
  std::string out;
  out.reserve(marked.size());
  for (size_t i = 0; i < marked.size();) {
    const size_t open = marked.find(kMark, i);
    const size_t close = open == std::string::npos ? open : marked.find(kMark, open + 1);
    if (close == std::string::npos) {
      out.append(marked, i, std::string::npos);
      break;
    }
    out.append(marked, i, open - i);
    out += name_of(std::string_view(marked).substr(open + 1, close - open - 1));
    i = close + 1;
  }
  return out;
}

std::string own_name(std::string_view name) { return std::string(name); }
}  // namespace

std::string parameter(std::string_view name) { return kMark + std::string(name) + kMark; }

std::string show_parameters(std::string_view marked,
                            const std::function<std::string(std::string_view)>& name_of) {
  return name_of ? render(marked, name_of) : render(marked, own_name);
}

InputError::InputError(const std::string& message)
    : std::runtime_error(render(message, own_name)),
      marked_(std::make_shared<const std::string>(message)) {}

std::string InputError::text(const std::function<std::string(std::string_view)>& name_of) const {
  return render(*marked_, name_of);
}

InputError InputError::prefixed(const std::string& prefix) const {
  return InputError(prefix + *marked_);
}

}  // namespace cover
