// Bird's-eye difference-matrix rows: exact key distances to every place, then the image search
// on the query's finalists (the two stages of birds_eye_match.hpp).
#include <algorithm>
#include <limits>

#include "loopscan/core/matching/place_matcher.hpp"

namespace loopscan {
namespace {

class BirdsEyeMatcher final : public PlaceMatcher {
 public:
  BirdsEyeMatcher(const BirdsEyePlaceConfig& place, const BirdsEyeSearchConfig& search)
      : place_config_(place), search_(search) {
    validate(place);
  }

  void add(const Signature& place) override {
    places_.push_back(birds_eye_place(place, place_config_));
    spectra_.push_back(key_spectrum(places_.back(), place_config_.angles));
  }
  std::size_t size() const override { return places_.size(); }
  int components() const override { return 1; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    const BirdsEyeKeySpectrum q =
        key_spectrum(birds_eye_place(query, place_config_), place_config_.angles);
    rows.resize(1, static_cast<Eigen::Index>(places_.size()));
    for (std::size_t j = 0; j < places_.size(); ++j) {
      rows(0, static_cast<Eigen::Index>(j)) = match_key_spectra(q, spectra_[j]).distance;
    }
  }

  void rerank(const Signature& query, int query_index, int mask_width,
              Eigen::MatrixXd& rows) const override {
    const BirdsEyePlace q = birds_eye_place(query, place_config_);
    const BirdsEyeKeySpectrum qs = key_spectrum(q, place_config_.angles);
    const BirdsEyeImageSearch images(q, place_config_, search_);
    std::vector<int> allowed;
    for (int j = 0; j < static_cast<int>(rows.cols()); ++j) {
      if (std::abs(query_index - j) >= mask_width) allowed.push_back(j);
    }
    const std::size_t f =
        std::min(allowed.size(), static_cast<std::size_t>(std::max(0, search_.finalists)));
    const auto by_key = [&](int a, int b) {
      return rows(0, a) < rows(0, b) || (rows(0, a) == rows(0, b) && a < b);
    };
    std::partial_sort(allowed.begin(), allowed.begin() + static_cast<std::ptrdiff_t>(f),
                      allowed.end(), by_key);
    Eigen::RowVectorXd out =
        Eigen::RowVectorXd::Constant(rows.cols(), std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < f; ++i) {
      const int j = allowed[i];
      const double yaw = match_key_spectra(qs, spectra_[j]).yaw_rad;
      out(j) = birds_eye_distance(images.pose(places_[j], yaw));
    }
    rows.row(0) = out;
  }

 private:
  BirdsEyePlaceConfig place_config_;
  BirdsEyeSearchConfig search_;
  std::vector<BirdsEyePlace> places_;
  std::vector<BirdsEyeKeySpectrum> spectra_;
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_birds_eye_matcher(const BirdsEyePlaceConfig& place,
                                                     const BirdsEyeSearchConfig& search) {
  return std::make_unique<BirdsEyeMatcher>(place, search);
}

}  // namespace loopscan
