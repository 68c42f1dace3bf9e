// Bird's-eye places: the image and the key packed as bytes (the stored form, 5,040 bytes with
// the default config), followed in memory by the key's angular spectrum. The index is the key
// itself: every eligible place's key is matched (about a microsecond a place) and the best
// become the candidates, whose images the exact distance then searches (birds_eye_match.hpp).
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "loopscan/core/database/place_store.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"

namespace loopscan {
namespace {

std::size_t floats_for_bytes(std::size_t bytes) { return (bytes + sizeof(float) - 1) / sizeof(float); }

class BirdsEyeStore final : public PlaceStore {
  struct PlaceQuery : Query {
    BirdsEyePlace place;
    BirdsEyeKeySpectrum spectrum;
  };

 public:
  BirdsEyeStore(const BirdsEyePlaceConfig& place, const BirdsEyeSearchConfig& search)
      : PlaceStore(payload_of(place), payload_of(place) + spectrum_floats(place), 0),
        place_config_((validate(place), place)),
        search_(search),
        cells_(static_cast<std::size_t>(image_side(place)) * image_side(place)),
        key_values_(static_cast<std::size_t>(place.rings) * place.angles) {}

  int components() const override { return 1; }

  void encode(const Signature& s, float* payload) const override {
    pack(birds_eye_place(s, place_config_), payload);
  }

  void append(const float* payload) override {
    std::vector<float> record(static_cast<std::size_t>(payload_floats()) +
                              spectrum_floats(place_config_));
    std::copy(payload, payload + payload_floats(), record.begin());
    const BirdsEyeKeySpectrum s = key_spectrum(unpack(payload), place_config_.angles);
    float* out = record.data() + payload_floats();
    out[0] = static_cast<float>(s.norm);
    std::copy(s.re.begin(), s.re.end(), out + 1);
    std::copy(s.im.begin(), s.im.end(), out + 1 + s.re.size());
    arena_.append(record.data());
  }

  void indexed_up_to(std::size_t) override {}  // the records hold the key spectra

  std::unique_ptr<Query> prepare(const Signature& s) const override {
    auto q = std::make_unique<PlaceQuery>();
    q->place = birds_eye_place(s, place_config_);
    q->spectrum = key_spectrum(q->place, place_config_.angles);
    return q;
  }

  void distances(const Query& query, const float* record, double* out) const override {
    out[0] = birds_eye_distance(pose(static_cast<const PlaceQuery&>(query), record));
  }

  void candidates(const Query& query, std::size_t count, std::size_t /*pool*/,
                  const Eligible& eligible, std::size_t n_places,
                  std::vector<std::size_t>& out) const override {
    const BirdsEyeKeySpectrumView q = view(static_cast<const PlaceQuery&>(query).spectrum);
    std::vector<std::pair<double, std::size_t>> scored;
    for (std::size_t i = 0; i < n_places; ++i) {
      if (eligible(i)) scored.emplace_back(match_key_spectra(q, spectrum(record(i))).distance, i);
    }
    const std::size_t n = std::min(count, scored.size());
    std::partial_sort(scored.begin(), scored.begin() + static_cast<std::ptrdiff_t>(n),
                      scored.end());
    out.clear();
    for (std::size_t j = 0; j < n; ++j) out.push_back(scored[j].second);
  }

  std::optional<BirdsEyePose> ground_pose(const Query& query, const float* record) const override {
    return pose(static_cast<const PlaceQuery&>(query), record);
  }

  std::size_t index_bytes() const override { return 0; }

 private:
  static std::size_t payload_of(const BirdsEyePlaceConfig& c) {
    return floats_for_bytes(static_cast<std::size_t>(image_side(c)) * image_side(c) +
                            static_cast<std::size_t>(c.rings) * c.angles);
  }
  // The norm, then the real and imaginary parts (rings x (angles / 2 + 1) each).
  static std::size_t spectrum_floats(const BirdsEyePlaceConfig& c) {
    return 1 + 2 * static_cast<std::size_t>(c.rings) * (c.angles / 2 + 1);
  }

  void pack(const BirdsEyePlace& place, float* payload) const {
    auto* bytes = reinterpret_cast<unsigned char*>(payload);
    std::memset(bytes, 0, payload_floats() * sizeof(float));
    std::memcpy(bytes, place.image.data(), cells_);
    std::memcpy(bytes + cells_, place.key.data(), key_values_);
  }
  BirdsEyePlace unpack(const float* payload) const {
    const auto* bytes = reinterpret_cast<const unsigned char*>(payload);
    BirdsEyePlace place;
    place.side = image_side(place_config_);
    place.image.assign(bytes, bytes + cells_);
    place.key.resize(key_values_);
    std::memcpy(place.key.data(), bytes + cells_, key_values_);
    return place;
  }
  BirdsEyeKeySpectrumView spectrum(const float* record) const {
    const float* s = record + payload_floats();
    const std::size_t terms = static_cast<std::size_t>(place_config_.rings) *
                              (place_config_.angles / 2 + 1);
    return {place_config_.rings, place_config_.angles, s + 1, s + 1 + terms, s[0]};
  }
  BirdsEyePose pose(const PlaceQuery& q, const float* record) const {
    const double yaw = match_key_spectra(view(q.spectrum), spectrum(record)).yaw_rad;
    return birds_eye_pose(q.place, unpack(record), yaw, place_config_, search_);
  }

  BirdsEyePlaceConfig place_config_;
  BirdsEyeSearchConfig search_;
  std::size_t cells_, key_values_;
};

}  // namespace

std::unique_ptr<PlaceStore> make_birds_eye_store(const BirdsEyePlaceConfig& place,
                                                 const BirdsEyeSearchConfig& search) {
  return std::make_unique<BirdsEyeStore>(place, search);
}

}  // namespace loopscan
