#pragma once
// Umbrella header of the report module.
#include "loopscan/report/colormap.hpp"
#include "loopscan/report/frame.hpp"
#include "loopscan/report/heatmap.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "loopscan/report/svg_text.hpp"
