#include "learner/training_observer.h"

namespace juggle {

const char* PhaseName(LoopPhase phase) {
  switch (phase) {
    case LoopPhase::kStarting: return "starting";
    case LoopPhase::kWaitingForData: return "waiting for data";
    case LoopPhase::kUpdating: return "updating";
    case LoopPhase::kEvaluating: return "evaluating";
    case LoopPhase::kCheckpointing: return "checkpointing";
    case LoopPhase::kFinished: return "finished";
  }
  return "unknown";
}

}  // namespace juggle
