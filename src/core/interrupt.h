// Ctrl-C as a request to stop at the next safe point (a training run checkpoints and returns)
// rather than a kill: while an InterruptRequest lives, SIGINT only sets a flag; the handler that
// was there before comes back when it goes out of scope, also when an exception leaves it.
#pragma once

namespace motionfork {

class InterruptRequest {
 public:
  InterruptRequest();  // clears the flag and installs the handler
  ~InterruptRequest();
  InterruptRequest(const InterruptRequest&) = delete;
  InterruptRequest& operator=(const InterruptRequest&) = delete;
  static bool requested();  // SIGINT arrived since the newest InterruptRequest was made
};

}  // namespace motionfork
