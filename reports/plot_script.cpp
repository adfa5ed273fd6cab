// Gnuplot scripts that hold no input as code, and the runner that draws them without a shell
// (reports/plot_script.hpp).
#include "reports/plot_script.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <exception>
#include <future>
#include <string_view>

#include "core/parallel.hpp"

extern char** environ;

namespace dynid {

namespace {

constexpr std::size_t kMaxPlotText = 200;  // bytes of a title or label kept

/// The length of the UTF-8 sequence starting at text[i], or 0 when it is not a valid one.
std::size_t utf8Length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  std::size_t n = 0;
  unsigned min = 0;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF)
    n = 2, min = 0x80;
  else if (c >= 0xE0 && c <= 0xEF)
    n = 3, min = 0x800;
  else if (c >= 0xF0 && c <= 0xF4)
    n = 4, min = 0x10000;
  else
    return 0;
  if (i + n > text.size()) return 0;
  unsigned code = c & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

/// The text between the quotes: `quote` kept (the caller splits there) or replaced (data: '"'
/// shown as '\''),
/// enhanced-text characters escaped, control characters as spaces, invalid UTF-8 as '?'.
std::string plotTextBody(std::string_view text, char quote) {
  std::string out;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < text.size();) {
    if (kept >= kMaxPlotText) {
      out += "...";
      break;
    }
    const std::size_t n = utf8Length(text, i);
    if (n == 0) {
      out += '?';
      ++i, ++kept;
      continue;
    }
    if (n > 1) {
      out.append(text.substr(i, n));
      i += n, kept += n;
      continue;
    }
    const char c = text[i];
    ++i, ++kept;
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      out += ' ';
    } else if (c == '"' && quote == '"') {
      out += '\'';
    } else {
      if (std::string_view("^_@&~{}\\").find(c) != std::string_view::npos) out += '\\';
      out += c;
    }
  }
  return out;
}

/// Writes all of `script` to gnuplot's stdin while reading its stdout (either may fill its pipe
/// first); at most kMaxSvgBytes are read. False on an I/O error or an oversized figure.
constexpr std::size_t kMaxSvgBytes = std::size_t{256} << 20;
bool exchange(int in, int out, const std::string& script, std::string& svg) {
  std::size_t written = 0;
  if (script.empty()) ::close(in), in = -1;
  while (out >= 0) {
    pollfd fds[2] = {{out, POLLIN, 0}, {in, POLLOUT, 0}};
    const int ready = ::poll(fds, in >= 0 ? 2 : 1, -1);
    if (ready < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (in >= 0 && (fds[1].revents & (POLLOUT | POLLERR | POLLHUP)) != 0) {
      const ssize_t n = ::write(in, script.data() + written, script.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
      if ((n < 0 && errno != EINTR && errno != EAGAIN) || written == script.size())
        ::close(in), in = -1;  // done, or gnuplot stopped reading (EPIPE)
    }
    if ((fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
      char buffer[1 << 16];
      const ssize_t n = ::read(out, buffer, sizeof(buffer));
      if (n > 0) {
        svg.append(buffer, static_cast<std::size_t>(n));
        if (svg.size() > kMaxSvgBytes) break;
      } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
        break;
      }
    }
  }
  if (in >= 0) ::close(in);
  if (out >= 0) ::close(out);
  return svg.size() <= kMaxSvgBytes;
}

}  // namespace

PlotText gnuplotString(std::string_view text) {
  // Single-quoted pieces joined by a double-quoted quote ('o'."'".'brien'): gnuplot reads a
  // doubled quote ('') at a string's start as an empty string, so quotes are never doubled.
  const std::string body = plotTextBody(text, '\'');
  std::string quoted(1, '\'');
  for (const char c : body)
    if (c == '\'')
      quoted.append("'.\"'\".'");
    else
      quoted.append(1, c);
  quoted.append(1, '\'');
  return PlotText(std::move(quoted));
}

PlotText gnuplotDataString(std::string_view text) {
  std::string quoted(1, '"');
  quoted.append(plotTextBody(text, '"')).append(1, '"');
  return PlotText(std::move(quoted));
}

void PlotRows::append(std::initializer_list<double> values) { append(std::vector<double>(values)); }

void PlotRows::append(const std::vector<double>& values) {
  std::array<char, 32> buffer;
  bool first = true;
  for (double x : values) {
    if (!first) text_ += ' ';
    first = false;
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x,
                                      std::chars_format::general, 9);
    text_.append(buffer.data(), result.ptr);
  }
  text_ += '\n';
}

void PlotRows::append(std::string_view label, std::initializer_list<double> values) {
  text_ += gnuplotDataString(label).quoted();
  if (values.size() > 0) text_ += ' ';
  append(values);
}

PlotScript& PlotScript::operator<<(int x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(long x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(unsigned long x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(double x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(const PlotText& text) {
  out_ << text.quoted();
  return *this;
}
PlotScript& PlotScript::operator<<(const PlotRows& rows) {
  out_ << rows.text();
  return *this;
}

std::optional<std::string> gnuplotSvg(const PlotScript& plot) {
  const char* configured = std::getenv("DYNID_GNUPLOT");
  std::string program = configured != nullptr && *configured != '\0' ? configured : "gnuplot";
  int in[2], out[2];
  if (::pipe2(in, O_CLOEXEC) != 0) return std::nullopt;
  if (::pipe2(out, O_CLOEXEC) != 0) {
    ::close(in[0]), ::close(in[1]);
    return std::nullopt;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  // gnuplot starts with no signal blocked, whatever this thread blocks (drawConcurrently).
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  char* argv[] = {program.data(), nullptr};
  pid_t pid = -1;
  // posix_spawnp: the program's name is looked up on the PATH, its path used as it is; no shell.
  const int spawned = ::posix_spawnp(&pid, program.c_str(), &actions, &attributes, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(in[0]), ::close(out[1]);
  if (spawned != 0) {
    ::close(in[1]), ::close(out[0]);
    return std::nullopt;
  }
  // A gnuplot that stops reading must not kill this process with SIGPIPE: blocked on this
  // thread while writing, and a pending one taken back before unblocking.
  sigset_t pipe_signal, previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
  ::fcntl(in[1], F_SETFL, O_NONBLOCK);
  std::string svg;
  const bool whole = exchange(in[1], out[0], plot.str(), svg);
  const timespec no_wait{0, 0};
  while (sigtimedwait(&pipe_signal, nullptr, &no_wait) > 0) {
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (!whole) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!whole || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  if (svg.find("<svg") == std::string::npos || svg.find("</svg>") == std::string::npos)
    return std::nullopt;
  return svg;
}

std::vector<std::optional<std::string>> drawConcurrently(
    const std::vector<std::function<std::optional<std::string>()>>& draws) {
  std::vector<std::future<std::optional<std::string>>> running;
  running.reserve(draws.size());
  {
    const TerminationSignalsBlocked inherited;  // the signals stay the main thread's
    for (const auto& draw : draws) running.push_back(std::async(std::launch::async, draw));
  }
  std::vector<std::optional<std::string>> out;
  std::exception_ptr failure;
  for (auto& r : running) {  // every one waited for before any exception leaves
    try {
      out.push_back(r.get());
    } catch (...) {
      if (!failure) failure = std::current_exception();
      out.emplace_back();
    }
  }
  if (failure) std::rethrow_exception(failure);
  return out;
}

}  // namespace dynid
