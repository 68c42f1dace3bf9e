#pragma once
// Precision-recall figures annotated with the protocol's metrics.
#include <string>
#include <vector>

#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/report/plot.hpp"

namespace loopscan::report {

// Series with x = recall, y = precision, in the curve's walk order.
Series pr_series(const std::vector<eval::PrPoint>& curve, const std::string& name,
                 const std::string& color = "");

// "AUC=0.xxxx, recall@100%P=0.xxxx" of a series read as (recall, precision), computed with the
// same functions as eval::evaluate_matches so figure and table agree.
std::string pr_metrics_text(const Series& curve);

// PR curve(s) on [0, 1]². One curve: title "<title> — AUC=0.xxxx, recall@100%P=0.xxxx".
// Several curves: the title is kept and each legend entry gets " — AUC=..., recall@100%P=...".
std::string pr_curve_svg(const std::vector<Series>& curves, const std::string& title);

}  // namespace loopscan::report
