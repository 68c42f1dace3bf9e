// Scan Context places: packed spectra (scan_context_spectra.hpp); the index is a KD-tree over
// the ring key (per ring the sector sum of the normalised structure half: invariant to yaw and
// mirroring), read in place from the packed spectra, where it is each ring's DC term.
#include "loopscan/core/key_index.hpp"
#include "loopscan/core/place_store.hpp"

namespace loopscan {
namespace {

class ScanContextStore final : public PlaceStore {
  struct SpectraQuery : Query {
    ScanContextSpectra::Query spectra;
    std::vector<float> key;
  };

 public:
  explicit ScanContextStore(const ScanContextConfig& config)
      : PlaceStore(2 * static_cast<std::size_t>(config.rings) * config.sectors),
        spectra_(config),
        index_({config.rings, 0, static_cast<std::size_t>(config.sectors)}, &arena_) {}

  int components() const override { return 2; }
  void encode(const Signature& signature, float* payload) const override {
    spectra_.pack(signature, payload);
  }
  void indexed_up_to(std::size_t n) override { index_.extend(n); }

  std::unique_ptr<Query> prepare(const Signature& signature) const override {
    auto q = std::make_unique<SpectraQuery>();
    q->spectra = spectra_.prepare(signature);
    for (int r = 0; r < spectra_.rings(); ++r) {
      q->key.push_back(spectra_.ring_key(q->spectra.packed.data(), r));
    }
    return q;
  }

  void distances(const Query& query, const float* payload, double* out) const override {
    float best[2];
    spectra_.best_dots(static_cast<const SpectraQuery&>(query).spectra, payload, best);
    out[0] = (1.0 - double(best[0])) / 2.0;
    out[1] = (1.0 - double(best[1])) / 2.0;
  }

  void candidates(const Query& query, std::size_t count, const Eligible& eligible, std::size_t,
                  std::vector<std::size_t>& out) const override {
    std::vector<std::pair<float, std::size_t>> near;
    index_.nearest(static_cast<const SpectraQuery&>(query).key.data(), count, eligible, near);
    out.clear();
    for (const auto& [d, i] : near) out.push_back(i);
  }

  std::optional<SectorAlignment> align(const Query& query, const float* payload) const override {
    return spectra_.align(static_cast<const SpectraQuery&>(query).spectra, payload, 0);
  }
  int sectors() const override { return spectra_.sectors(); }
  std::size_t index_bytes() const override { return index_.memory_bytes(); }

 private:
  ScanContextSpectra spectra_;
  KeyIndex index_;
};

}  // namespace

std::unique_ptr<PlaceStore> make_scan_context_store(const ScanContextConfig& config) {
  return std::make_unique<ScanContextStore>(config);
}

}  // namespace loopscan
