// bounce_scene_fuzz [--seed S] [--cases N] [--minutes M] [--repros DIR] [--verbose]: runs cases 0, 1, ... of seed S
// (until N cases or M minutes, whichever comes first; 100 cases when neither is given) and writes a repro file into DIR
// (default tests/native/fuzz_repros) for each case that fails, so that SceneFuzz.Repros replays it. Each case runs in a
// child process: a crash, an abort or a hang (over a minute, then over five minutes run again) fails that case
// alone, and the run goes on. Its counts so far are printed every 1,000 cases. --verbose prints why the engine
// refused the cases it did not render (an error with its message, which is allowed).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "scene_fuzz.h"

namespace {

using namespace bounce::test::fuzz;

// A case that outlasts the first limit is run again under the second before it counts as hung: a machine busy
// with other work (a CI run beside a long fuzz run at nice 19) starved cases of 8-20 s past a minute.
constexpr unsigned kCaseTimeLimitSeconds = 60, kRetryTimeLimitSeconds = 300;

struct CaseResult {
  std::string failure;  // "" when the case passed
  bool rendered = false;
  std::string refusal;  // why the engine refused to render, when it did
};

// Runs one case in a child, which reports through a pipe: "R" (rendered) or "E<refusal>" on the first line,
// then its failures. A signal ends it without a report, which is a failure of its own.
CaseResult run_isolated(const Repro& repro, unsigned time_limit_seconds) {
  int pipe_ends[2];
  if (pipe(pipe_ends) != 0) return {std::string("pipe: ") + std::strerror(errno)};
  const pid_t child = fork();
  if (child < 0) return {std::string("fork: ") + std::strerror(errno)};
  if (child == 0) {
    close(pipe_ends[0]);
    alarm(time_limit_seconds);
    const Outcome outcome = run_case(generate(repro.seed, repro.index));
    std::string report = outcome.rendered ? "R\n" : "E" + outcome.refusal + "\n";
    for (std::size_t i = 0; i < outcome.failures.size(); ++i) report += (i == 0 ? "" : "; ") + outcome.failures[i];
    if (write(pipe_ends[1], report.data(), report.size()) < 0) _exit(2);
    _exit(outcome.failures.empty() ? 0 : 1);
  }
  close(pipe_ends[1]);
  std::string report;
  char buffer[4096];
  for (ssize_t n; (n = read(pipe_ends[0], buffer, sizeof buffer)) > 0;) report.append(buffer, std::size_t(n));
  close(pipe_ends[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (WIFSIGNALED(status))
    return {WTERMSIG(status) == SIGALRM ? "hung for over " + std::to_string(time_limit_seconds) + " s"
                                        : std::string("crashed: ") + strsignal(WTERMSIG(status))};
  const std::size_t line_end = std::min(report.find('\n'), report.size());
  CaseResult result;
  result.rendered = report.starts_with("R");
  if (!result.rendered && line_end > 0) result.refusal = report.substr(1, line_end - 1);
  result.failure = WEXITSTATUS(status) == 0 ? "" : report.substr(std::min(line_end + 1, report.size()));
  if (WEXITSTATUS(status) != 0 && result.failure.empty())
    result.failure = "exited with status " + std::to_string(WEXITSTATUS(status));
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t seed = 1, cases = UINT64_MAX;
  double minutes = 0.0;
  std::string repro_dir = BOUNCE_FUZZ_REPRO_DIR;
  bool verbose = false;
  for (int i = 1; i < argc; i += 2) {
    const std::string option = argv[i], value = i + 1 < argc ? argv[i + 1] : "";
    if (option == "--verbose") {
      verbose = true;
      --i;
    } else if (option == "--seed") {
      seed = std::strtoull(value.c_str(), nullptr, 10);
    } else if (option == "--cases") {
      cases = std::strtoull(value.c_str(), nullptr, 10);
    } else if (option == "--minutes") {
      minutes = std::strtod(value.c_str(), nullptr);
    } else if (option == "--repros") {
      repro_dir = value;
    } else {
      std::fprintf(stderr, "usage: %s [--seed S] [--cases N] [--minutes M] [--repros DIR] [--verbose]\n", argv[0]);
      return 2;
    }
  }
  if (cases == UINT64_MAX && minutes <= 0.0) cases = 100;
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed_minutes = [&] {
    return std::chrono::duration<double, std::ratio<60>>(std::chrono::steady_clock::now() - start).count();
  };
  uint64_t index = 0, failed = 0, rendered = 0;
  for (; index < cases && (minutes <= 0.0 || elapsed_minutes() < minutes); ++index) {
    const Repro repro{seed, index};
    if (index > 0 && index % 1000 == 0) {  // a long run shows it is alive, and what it has done if it is stopped
      std::printf("seed %llu: %llu cases, %llu rendered, %llu failed (%.1f min)\n",
                  static_cast<unsigned long long>(seed), static_cast<unsigned long long>(index),
                  static_cast<unsigned long long>(rendered), static_cast<unsigned long long>(failed),
                  elapsed_minutes());
      std::fflush(stdout);
    }
    CaseResult result = run_isolated(repro, kCaseTimeLimitSeconds);
    if (result.failure.starts_with("hung")) result = run_isolated(repro, kRetryTimeLimitSeconds);
    rendered += result.rendered;
    if (verbose && !result.rendered)
      std::printf("case %llu refused: %s\n", static_cast<unsigned long long>(index), result.refusal.c_str());
    if (result.failure.empty()) continue;
    ++failed;
    const std::string path = repro_dir + "/seed" + std::to_string(seed) + "_case" + std::to_string(index) + ".txt";
    write_repro(path, repro, result.failure);
    std::printf("FAIL seed %llu case %llu: %s\n  repro: %s\n", static_cast<unsigned long long>(seed),
                static_cast<unsigned long long>(index), result.failure.c_str(), path.c_str());
    std::fflush(stdout);
  }
  std::printf("seed %llu: %llu cases in %.2f min, %llu rendered, %llu failed\n", static_cast<unsigned long long>(seed),
              static_cast<unsigned long long>(index), elapsed_minutes(), static_cast<unsigned long long>(rendered),
              static_cast<unsigned long long>(failed));
  return failed == 0 ? 0 : 1;
}
