#include "launch/worker_launcher.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "launch/worker_place.h"

extern char** environ;

namespace motionfork {

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kLauncherFlags[] = {"--nproc-per-node", "--nnodes", "--node-rank",
                                          "--master-addr", "--master-port"};
constexpr int kDefaultMasterPort = 29500;  // torchrun's

volatile sig_atomic_t g_signal = 0;

void RememberSignal(int sig) { g_signal = sig; }

struct Worker {
  int rank = 0;
  pid_t pid = -1;
  bool running = false;
  int status = 0;
};

std::string Describe(const Worker& w) {
  const std::string who =
      "worker rank " + std::to_string(w.rank) + " (pid " + std::to_string(w.pid) + ")";
  if (WIFSIGNALED(w.status)) {
    return who + " was killed by signal " + std::to_string(WTERMSIG(w.status)) + " (" +
           strsignal(WTERMSIG(w.status)) + ")";
  }
  return who + " exited with status " + std::to_string(WEXITSTATUS(w.status));
}

int ExitCode(int status) {
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : WEXITSTATUS(status);
}

// The environment of a worker: this process's, with the run's variables replaced.
std::vector<std::string> WorkerEnvironment(
    const std::vector<std::pair<std::string, std::string>>& set) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string entry(*e);
    const std::string name = entry.substr(0, entry.find('='));
    const bool replaced =
        std::any_of(set.begin(), set.end(), [&](const auto& kv) { return kv.first == name; });
    if (!replaced) env.push_back(entry);
  }
  for (const auto& [name, value] : set) env.push_back(name + "=" + value);
  return env;
}

std::vector<char*> Pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (std::string& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// Reaps workers that ended; returns the first one that failed (nullptr if none did).
Worker* Reap(std::vector<Worker>& workers, int* running) {
  Worker* failed = nullptr;
  for (Worker& w : workers) {
    if (!w.running) continue;
    int status = 0;
    if (waitpid(w.pid, &status, WNOHANG) == w.pid) {
      w.running = false;
      w.status = status;
      --*running;
      if (!failed && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) failed = &w;
    }
  }
  return failed;
}

void SignalAll(std::vector<Worker>& workers, int sig) {
  for (const Worker& w : workers)
    if (w.running) kill(w.pid, sig);
}

// Waits up to `limit` for the running workers to end.
void WaitFor(std::vector<Worker>& workers, int* running, std::chrono::milliseconds limit) {
  const auto deadline = Clock::now() + limit;
  while (*running > 0 && Clock::now() < deadline) {
    Reap(workers, running);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace

bool LaunchRequested(const LaunchOptions& o) { return o.nproc_per_node > 1 || o.nnodes > 1; }

void CheckLaunchOptions(const LaunchOptions& o) {
  if (o.nproc_per_node < 1)
    throw std::invalid_argument("--nproc-per-node: expected >= 1, found " +
                                std::to_string(o.nproc_per_node));
  if (o.nnodes < 1)
    throw std::invalid_argument("--nnodes: expected >= 1, found " + std::to_string(o.nnodes));
  if (o.node_rank < 0 || o.node_rank >= o.nnodes) {
    throw std::invalid_argument("--node-rank: expected 0.." + std::to_string(o.nnodes - 1) +
                                " (--nnodes " + std::to_string(o.nnodes) + "), found " +
                                std::to_string(o.node_rank));
  }
  if (o.master_port < 0 || o.master_port > 65535)
    throw std::invalid_argument("--master-port: expected 1..65535, found " +
                                std::to_string(o.master_port));
  if (o.nnodes > 1 && o.master_addr.empty()) {
    throw std::invalid_argument(
        "--master-addr: expected the host of node 0 (reachable from every node) when --nnodes is " +
        std::to_string(o.nnodes) + ", found none");
  }
}

std::vector<std::string> WithoutLauncherFlags(const std::vector<std::string>& argv) {
  std::vector<std::string> out;
  for (size_t i = 0; i < argv.size(); ++i) {
    bool skip = false;
    for (const char* flag : kLauncherFlags) {
      const std::string f(flag);
      if (argv[i] == f) {
        skip = true;
        ++i;  // and its value
        break;
      }
      if (argv[i].rfind(f + "=", 0) == 0) {
        skip = true;
        break;
      }
    }
    if (!skip) out.push_back(argv[i]);
  }
  return out;
}

int FreeLocalPort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof(addr);
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    const std::string why = std::strerror(errno);
    close(fd);
    throw std::runtime_error("cannot find a free local port: " + why);
  }
  close(fd);
  return ntohs(addr.sin_port);
}

int LaunchWorkers(const LaunchOptions& o, const std::vector<std::string>& argv,
                  const std::function<void(const std::string&)>& note) {
  CheckLaunchOptions(o);
  const int world = o.nproc_per_node * o.nnodes;
  const std::string addr = o.master_addr.empty() ? "127.0.0.1" : o.master_addr;
  const int port =
      o.master_port > 0 ? o.master_port : (o.nnodes == 1 ? FreeLocalPort() : kDefaultMasterPort);
  const std::string threads = std::to_string(std::max(1, CoresAvailable() / o.nproc_per_node));
  if (note) {
    note("starting " + std::to_string(o.nproc_per_node) + " workers (ranks " +
         std::to_string(o.node_rank * o.nproc_per_node) + ".." +
         std::to_string((o.node_rank + 1) * o.nproc_per_node - 1) + " of " + std::to_string(world) +
         ", master " + addr + ":" + std::to_string(port) + ", up to " + threads +
         " thread(s) each)");
  }
  std::vector<std::string> args = argv;
  std::vector<char*> arg_ptrs = Pointers(args);
  std::vector<Worker> workers(o.nproc_per_node);
  struct sigaction act {};
  act.sa_handler = RememberSignal;
  sigemptyset(&act.sa_mask);
  struct sigaction old_int {
  }, old_term{};
  sigaction(SIGINT, &act, &old_int);
  sigaction(SIGTERM, &act, &old_term);
  int running = 0;
  for (int i = 0; i < o.nproc_per_node; ++i) {
    const int rank = o.node_rank * o.nproc_per_node + i;
    std::vector<std::pair<std::string, std::string>> set = {
        {"RANK", std::to_string(rank)},
        {"WORLD_SIZE", std::to_string(world)},
        {"LOCAL_RANK", std::to_string(i)},
        {"LOCAL_WORLD_SIZE", std::to_string(o.nproc_per_node)},
        {"GROUP_RANK", std::to_string(o.node_rank)},
        {"MASTER_ADDR", addr},
        {"MASTER_PORT", std::to_string(port)}};
    for (const char* name : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MOTIONFORK_THREADS"}) {
      if (!std::getenv(name)) set.emplace_back(name, threads);
    }
    std::vector<std::string> env = WorkerEnvironment(set);
    std::vector<char*> env_ptrs = Pointers(env);
    const pid_t pid = fork();
    if (pid < 0) {
      SignalAll(workers, SIGTERM);
      throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(errno));
    }
    if (pid == 0) {
      execve("/proc/self/exe", arg_ptrs.data(), env_ptrs.data());
      _exit(127);
    }
    workers[i] = {rank, pid, true, 0};
    ++running;
  }
  int code = 0;
  while (running > 0) {
    if (g_signal) {  // passed on, as torchrun does; the workers stop and are reaped below
      SignalAll(workers, g_signal);
      code = 128 + g_signal;
      g_signal = 0;
    }
    if (Worker* failed = Reap(workers, &running)) {
      if (code == 0) code = ExitCode(failed->status);
      if (note) {
        note(Describe(*failed) + "; " +
             (running > 0 ? "waiting " + std::to_string(o.grace.count()) + " s for the other " +
                                std::to_string(running) + " worker(s) to stop"
                          : std::string("no worker left")));
      }
      WaitFor(workers, &running, o.grace);
      if (running > 0) {
        if (note) note("terminating " + std::to_string(running) + " worker(s) still running");
        SignalAll(workers, SIGTERM);
        WaitFor(workers, &running, std::chrono::seconds(10));
        SignalAll(workers, SIGKILL);
        WaitFor(workers, &running, std::chrono::seconds(10));
      }
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  return code;
}

}  // namespace motionfork
