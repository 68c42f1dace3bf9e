#pragma once
// Umbrella header of the evaluation module.
#include "loopscan/eval/best_match.hpp"
#include "loopscan/eval/pairwise.hpp"
#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/eval/protocol.hpp"
