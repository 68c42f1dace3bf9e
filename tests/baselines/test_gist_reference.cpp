// The reference GIST variant against Lear's C GIST (the program the paper's authors call) on
// real images (../shared/data/real/gist-reference): the shared 256x256 inputs, and the original
// KITTI frames through the cover + centre crop.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "loopscan/baselines/gist.hpp"
#include "support/test_support.hpp"

namespace loopscan::baselines {
namespace {
namespace fs = std::filesystem;

fs::path reference() { return fs::path(test::shared_dir()) / "data/real/gist-reference"; }

Eigen::VectorXf read_vector(const fs::path& p) {
  std::ifstream in(p);
  std::vector<float> v;
  for (float x; in >> x;) v.push_back(x);
  return Eigen::Map<Eigen::VectorXf>(v.data(), static_cast<Eigen::Index>(v.size()));
}

double relative_l2(const Eigen::VectorXf& a, const Eigen::VectorXf& reference) {
  return (a - reference).norm() / reference.norm();
}

TEST(GistReference, MatchesLearsCGistOnEverySharedImage) {
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(reference()), reference());
  GistExtractor lear(GistConfig::lear_c());
  int images = 0;
  for (const auto& e : fs::directory_iterator(reference() / "input_256x256_gray")) {
    const cv::Mat image = cv::imread(e.path().string(), cv::IMREAD_GRAYSCALE);
    const std::string stem = e.path().stem().string();
    const Eigen::VectorXf ref = read_vector(reference() / "lear_c_gist" / (stem + ".txt"));
    ASSERT_EQ(ref.size(), 512) << stem;
    const double d = relative_l2(lear.describe(image), ref);
    std::printf("%s: relative L2 to Lear's C GIST %.2e\n", stem.c_str(), d);
    EXPECT_LT(d, 1e-3) << stem;
    ++images;
  }
  EXPECT_GE(images, 6);
}

TEST(GistReference, TheCropOfTheOriginalKittiFramesGivesTheSameGist) {
  const fs::path frames = fs::path(test::shared_dir()) / "data/real/kitti06-000000-000050/image_0";
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(reference()) && fs::exists(frames),
                               reference() << " and " << frames);
  GistExtractor lear(GistConfig::lear_c());
  for (const char* frame : {"000000", "000025", "000050"}) {
    const cv::Mat original =
        cv::imread((frames / (std::string(frame) + ".png")).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(original.cols, 1226);
    // The crop reproduces the shared input (made with the authors' preprocessing) pixel for pixel.
    const cv::Mat shared = cv::imread(
        (reference() / "input_256x256_gray" / ("kitti06_" + std::string(frame) + ".png")).string(),
        cv::IMREAD_GRAYSCALE);
    const cv::Mat crop = cover_and_crop(original, 256);
    ASSERT_EQ(crop.size(), shared.size());
    EXPECT_LE(cv::norm(crop, shared, cv::NORM_INF), 1.0) << frame;
    const Eigen::VectorXf ref =
        read_vector(reference() / "lear_c_gist" / ("kitti06_" + std::string(frame) + ".txt"));
    EXPECT_LT(relative_l2(lear.describe(original), ref), 1e-3) << frame;
  }
}

}  // namespace
}  // namespace loopscan::baselines
