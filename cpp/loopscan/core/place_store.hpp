#pragma once
// What the database needs from a descriptor: a fixed-length float payload per place (the
// stored form), exact distance components of a prepared query to one payload, and an index
// that proposes candidates. One implementation per method.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "loopscan/core/database.hpp"
#include "loopscan/core/payload_arena.hpp"
#include "loopscan/core/scan_context_spectra.hpp"

namespace loopscan {

using Eligible = std::function<bool(std::size_t)>;

class PlaceStore {
 public:
  struct Query {
    virtual ~Query() = default;
  };
  virtual ~PlaceStore() = default;

  int payload_floats() const { return static_cast<int>(arena_.floats_per_record()); }
  virtual int components() const = 0;  // 2 (structure, intensity) or 1
  // Throws std::invalid_argument when the signature has the wrong shape.
  virtual void encode(const Signature& signature, float* payload) const = 0;
  // Payloads [0, n) exist; index the new ones.
  virtual void indexed_up_to(std::size_t n) = 0;
  virtual std::unique_ptr<Query> prepare(const Signature& signature) const = 0;
  // out[c] = component c of the distance from the query to the payload.
  virtual void distances(const Query& query, const float* payload, double* out) const = 0;
  // Indexed retrieval: up to `count` eligible places, best candidates first.
  virtual void candidates(const Query& query, std::size_t count, const Eligible& eligible,
                          std::size_t n_places, std::vector<std::size_t>& out) const = 0;
  // Scan Context only: the sector alignment of the structure halves.
  virtual std::optional<SectorAlignment> align(const Query&, const float*) const {
    return std::nullopt;
  }
  virtual int sectors() const { return 0; }
  virtual std::size_t index_bytes() const = 0;

  PayloadArena& arena() { return arena_; }
  const PayloadArena& arena() const { return arena_; }

 protected:
  explicit PlaceStore(std::size_t payload_floats) : arena_(payload_floats) {}
  PayloadArena arena_;
};

std::unique_ptr<PlaceStore> make_scan_context_store(const ScanContextConfig& config);
std::unique_ptr<PlaceStore> make_m2dp_store(int columns);
std::unique_ptr<PlaceStore> make_delight_store(int columns);

}  // namespace loopscan
