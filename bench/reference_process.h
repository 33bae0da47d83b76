// A reference implementation running in its own process, asked for one timed run at a time, so
// that a benchmark can interleave it with its own calls (A/B in turns: this machine's speed drifts
// between seconds). The protocol is bench/reference_gsps.py's --serve: the child prints
// "ready <parameters>" once warmed up, then answers each "run" line with the milliseconds of one
// run; "quit" ends it.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace motionfork::bench {

class ReferenceProcess {
 public:
  // Starts argv[0] (looked up on PATH) with argv; waits for its "ready" line.
  explicit ReferenceProcess(const std::vector<std::string>& argv) {
    int to_child[2], from_child[2];
    if (pipe(to_child) != 0 || pipe(from_child) != 0)
      throw std::runtime_error("reference: cannot make pipes");
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("reference: cannot fork");
    if (pid_ == 0) {
      dup2(to_child[0], 0);
      dup2(from_child[1], 1);
      close(to_child[1]);
      close(from_child[0]);
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      execvp(args[0], args.data());
      std::fprintf(stderr, "reference: cannot run %s\n", args[0]);
      _exit(127);
    }
    close(to_child[0]);
    close(from_child[1]);
    in_ = fdopen(to_child[1], "w");
    out_ = fdopen(from_child[0], "r");
    const std::string first = ReadLine();
    if (first.rfind("ready", 0) != 0) {
      throw std::runtime_error(
          "reference: expected 'ready <parameters>' from " + argv[0] + " " +
          (argv.size() > 1 ? argv[1] : "") + ", got '" + first +
          "' (its error above; PyTorch missing? apt-get install python3-torch)");
    }
    parameters_ = std::atoll(first.c_str() + 5);
  }
  ReferenceProcess(const ReferenceProcess&) = delete;
  ReferenceProcess& operator=(const ReferenceProcess&) = delete;
  ~ReferenceProcess() {
    if (in_) {
      std::fputs("quit\n", in_);
      std::fclose(in_);
    }
    if (out_) std::fclose(out_);
    if (pid_ > 0) waitpid(pid_, nullptr, 0);
  }

  // A bench/reference_*.py script served on `threads` intra-op threads by Debian's python3-torch,
  // which installs for /usr/bin/python3 (another python3 may come first on PATH);
  // $MOTIONFORK_PYTHON chooses another interpreter.
  static std::unique_ptr<ReferenceProcess> Python(const std::string& script, int threads) {
    const char* python = std::getenv("MOTIONFORK_PYTHON");
    return std::make_unique<ReferenceProcess>(
        std::vector<std::string>{python ? python : "/usr/bin/python3", script, "--serve",
                                 "--threads", std::to_string(threads)});
  }

  long long parameters() const { return parameters_; }

  // One run's time in seconds, as the child measured it.
  double Run() {
    std::fputs("run\n", in_);
    std::fflush(in_);
    const std::string line = ReadLine();
    char* end = nullptr;
    const double ms = std::strtod(line.c_str(), &end);
    if (end == line.c_str() || !(ms > 0))
      throw std::runtime_error("reference: expected a time in ms, got '" + line + "'");
    return ms / 1e3;
  }

 private:
  std::string ReadLine() {
    std::string line;
    for (int c = std::fgetc(out_); c != EOF && c != '\n'; c = std::fgetc(out_))
      line.push_back(static_cast<char>(c));
    return line;
  }

  pid_t pid_ = -1;
  FILE* in_ = nullptr;
  FILE* out_ = nullptr;
  long long parameters_ = 0;
};

}  // namespace motionfork::bench
