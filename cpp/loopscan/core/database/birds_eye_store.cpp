// Bird's-eye places: the image and the key packed as bytes (the stored form, 5,040 bytes with
// the default config), followed in memory by the key's angular spectrum; the spectra again as
// bfloat16 in an arena of their own, for the key scan's bound. Every eligible
// place's key is matched (a fraction of a microsecond a place) and the best become the
// finalists, whose images the distance then searches (birds_eye_match.hpp): the exact query and
// the indexed one alike, as in the difference-matrix rows.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "loopscan/core/database/place_store.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"

namespace loopscan {
namespace {

std::size_t floats_for_bytes(std::size_t bytes) { return (bytes + sizeof(float) - 1) / sizeof(float); }

class BirdsEyeStore final : public PlaceStore {
  struct PlaceQuery : Query {
    PlaceQuery(BirdsEyePlace p, const BirdsEyePlaceConfig& config,
               const BirdsEyeSearchConfig& search)
        : place(std::move(p)),
          spectrum(key_spectrum(place, config.angles)),
          images(place, config, search) {}
    BirdsEyePlace place;
    BirdsEyeKeySpectrum spectrum;
    BirdsEyeImageSearch images;
    // The poses found by distances(), which ground_pose() then gives without a second search.
    mutable std::mutex mutex;
    mutable std::vector<std::pair<const float*, BirdsEyePose>> found;
  };

 public:
  BirdsEyeStore(const BirdsEyePlaceConfig& place, const BirdsEyeSearchConfig& search)
      : PlaceStore(payload_of(place),
                   payload_of(place) + packed_key_spectrum_floats(place.rings, place.angles), 0),
        place_config_((validate(place), place)),
        search_(search),
        cells_(static_cast<std::size_t>(image_side(place)) * image_side(place)),
        key_values_(static_cast<std::size_t>(place.rings) * place.angles) {}

  int components() const override { return 1; }

  void encode(const Signature& s, float* payload) const override {
    pack(birds_eye_place(s, place_config_), payload);
  }

  void append(const float* payload) override {
    std::vector<float> record(
        static_cast<std::size_t>(payload_floats()) +
        packed_key_spectrum_floats(place_config_.rings, place_config_.angles));
    std::copy(payload, payload + payload_floats(), record.begin());
    const BirdsEyeKeySpectrum s = key_spectrum(unpack(payload), place_config_.angles);
    pack_key_spectrum(s, record.data() + payload_floats());
    arena_.append(record.data());
    rounded_.append(reinterpret_cast<const float*>(s.rounded.data()));  // copied as bytes
  }

  void indexed_up_to(std::size_t) override {}  // the records hold the key spectra

  std::unique_ptr<Query> prepare(const Signature& s) const override {
    return std::make_unique<PlaceQuery>(birds_eye_place(s, place_config_), place_config_, search_);
  }

  void distances(const Query& query, const float* record, double* out) const override {
    const auto& q = static_cast<const PlaceQuery&>(query);
    const BirdsEyePose p = pose(q, record);
    {
      const std::lock_guard<std::mutex> lock(q.mutex);
      q.found.emplace_back(record, p);
    }
    out[0] = birds_eye_distance(p);
  }

  std::size_t finalists() const override {
    return static_cast<std::size_t>(std::max(1, search_.finalists));
  }

  void candidates(const Query& query, std::size_t count, std::size_t /*pool*/,
                  const Eligible& eligible, std::size_t n_places,
                  std::vector<std::size_t>& out) const override {
    const auto nearest = nearest_keys(
        view(static_cast<const PlaceQuery&>(query).spectrum), n_places, eligible,
        [&](std::size_t i) { return spectrum(i); }, count);
    out.clear();
    for (const auto& [distance, i] : nearest) out.push_back(i);
  }

  std::optional<BirdsEyePose> ground_pose(const Query& query, const float* record) const override {
    const auto& q = static_cast<const PlaceQuery&>(query);
    {
      const std::lock_guard<std::mutex> lock(q.mutex);
      for (const auto& [r, p] : q.found) {
        if (r == record) return p;
      }
    }
    return pose(q, record);
  }

  void set_birds_eye_search(const BirdsEyeSearchConfig& search) override {
    validate(search, place_config_);
    search_ = search;
  }

  std::size_t index_bytes() const override { return rounded_.memory_bytes(); }

 private:
  static std::size_t payload_of(const BirdsEyePlaceConfig& c) {
    return floats_for_bytes(static_cast<std::size_t>(image_side(c)) * image_side(c) +
                            static_cast<std::size_t>(c.rings) * c.angles);
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
  // The spectrum packed after the payload (with place i's bfloat16 copy, by index).
  BirdsEyeKeySpectrumView spectrum(const float* record) const {
    return packed_key_spectrum(record + payload_floats(), place_config_.rings,
                               place_config_.angles);
  }
  BirdsEyeKeySpectrumView spectrum(std::size_t i) const {
    return packed_key_spectrum(record(i) + payload_floats(), place_config_.rings,
                               place_config_.angles, rounded_.at(i));
  }
  BirdsEyePose pose(const PlaceQuery& q, const float* record) const {
    const double yaw = match_key_spectra(view(q.spectrum), spectrum(record)).yaw_rad;
    return q.images.pose(unpack(record), yaw);
  }

  BirdsEyePlaceConfig place_config_;
  BirdsEyeSearchConfig search_;
  std::size_t cells_, key_values_;
  // Per place, its key spectrum as bfloat16, contiguous: what the key scan's bound streams.
  PayloadArena rounded_{packed_rounded_floats(place_config_.rings, place_config_.angles)};
};

}  // namespace

std::unique_ptr<PlaceStore> make_birds_eye_store(const BirdsEyePlaceConfig& place,
                                                 const BirdsEyeSearchConfig& search) {
  return std::make_unique<BirdsEyeStore>(place, search);
}

}  // namespace loopscan
