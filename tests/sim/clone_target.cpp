// For the suites built on one clone of the renderer (loopscan_tests_sim_<clone>): skips every
// test where the CPU cannot run that clone's instructions.
#include <gtest/gtest.h>

namespace {

class CloneTarget : public ::testing::Environment {
 public:
  void SetUp() override {
#ifdef LOOPSCAN_SIM_ONLY_TARGET
    __builtin_cpu_init();
    if (!__builtin_cpu_supports(LOOPSCAN_SIM_ONLY_TARGET)) {
      GTEST_SKIP() << "this CPU does not run the renderer's " << LOOPSCAN_SIM_ONLY_TARGET
                   << " clone";
    }
#endif
  }
};

const ::testing::Environment* const kCloneTarget =
    ::testing::AddGlobalTestEnvironment(new CloneTarget);

}  // namespace
