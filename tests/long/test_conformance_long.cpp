// The long suite (label `long`, `scripts/test --long`): reference-mode M2DP over the whole
// k06 fixture, signatures and metrics (~40 s on 2 cores; its Jacobi SVDs take ~50 ms a place).
// The default suite compares every 20th place (Conformance.M2dpReferenceModeEveryTwentiethPlace).
#include "core/pipeline/conformance_support.hpp"

namespace loopscan {
namespace {

using conformance::describe_fixture;
using conformance::expect_metrics_match;
using conformance::expect_signatures_match;

TEST(Conformance, M2dpReferenceMode) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const SequenceSignatures ours = describe_fixture(Method::M2dp);
  expect_signatures_match(Method::M2dp, ours);  // the SVD signs match too (same Eigen routine)
  for (Fusion fu : {Fusion::Fused, Fusion::Structure, Fusion::Intensity}) {
    expect_metrics_match(Method::M2dp, ours.signatures, fu);
  }
}

}  // namespace
}  // namespace loopscan
