#pragma once
// What the database needs from a descriptor: a fixed-length float payload per place (the
// stored form), exact distance components of a prepared query to one payload, and an index
// that proposes candidates. One implementation per method.
#include <algorithm>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "loopscan/core/matching/scan_context_spectra.hpp"
#include "loopscan/core/payload_arena.hpp"

namespace loopscan {

using Eligible = std::function<bool(std::size_t)>;

class PlaceStore {
 public:
  struct Query {
    virtual ~Query() = default;
  };
  virtual ~PlaceStore() = default;

  // The stored form of a place (what encode writes and persistence saves).
  int payload_floats() const { return payload_floats_; }
  // Its leading floats that are float values (the scoring record); any rest holds packed
  // integers (Scan Context's uint16 spectral key), whose bit patterns may read as NaN.
  int value_floats() const { return value_floats_; }
  // Keeps a place's stored form; by default the whole payload is the scoring record.
  virtual void append(const float* payload) { arena_.append(payload); }
  virtual void stored(std::size_t i, float* out) const {
    std::copy(arena_.at(i), arena_.at(i) + payload_floats_, out);
  }
  virtual int components() const = 0;  // 2 (structure, intensity) or 1
  // Throws std::invalid_argument when the signature has the wrong shape.
  virtual void encode(const Signature& signature, float* payload) const = 0;
  // Payloads [0, n) exist; index the new ones.
  virtual void indexed_up_to(std::size_t n) = 0;
  virtual std::unique_ptr<Query> prepare(const Signature& signature) const = 0;
  // out[c] = component c of the distance from the query to the payload.
  virtual void distances(const Query& query, const float* payload, double* out) const = 0;
  // A cheaper first pass over indexed candidates (`slot`: the place's position in the last
  // candidates() output for this query): component distances that are never below
  // distances(). The database refines the best few with distances(). Default: exact.
  virtual bool partial_first_pass(const Query&) const { return false; }
  virtual void first_pass(const Query& query, std::size_t /*slot*/, const float* payload,
                          double* out) const {
    distances(query, payload, out);
  }
  // Methods whose distance is defined on the finalists of a first ranking over every place
  // (bird's-eye: the key's best, whose images are searched): how many finalists. Every query,
  // exact or indexed, then scores those candidates() of every eligible place, as the
  // difference-matrix rows do; 0: the exact query scores every eligible place.
  virtual std::size_t finalists() const { return 0; }
  // Indexed retrieval: up to `count` eligible places, best candidates first (`pool`: the
  // first stage's size where there are two stages).
  virtual void candidates(const Query& query, std::size_t count, std::size_t pool,
                          const Eligible& eligible, std::size_t n_places,
                          std::vector<std::size_t>& out) const = 0;
  // Scan Context only: the sector alignment of the structure halves.
  virtual std::optional<SectorAlignment> align(const Query&, const float*) const {
    return std::nullopt;
  }
  virtual int sectors() const { return 0; }
  // Bird's-eye places only: the place's metric pose in the query's frame (the image search),
  // and how later queries search (set before querying; not while queries run).
  virtual std::optional<BirdsEyePose> ground_pose(const Query&, const float*) const {
    return std::nullopt;
  }
  virtual void set_birds_eye_search(const BirdsEyeSearchConfig&) {}
  virtual std::size_t index_bytes() const = 0;

  // The scoring record of place i (what distances() and align() read).
  const float* record(std::size_t i) const { return arena_.at(i); }
  virtual std::size_t memory_bytes() const { return arena_.memory_bytes() + index_bytes(); }

 protected:
  PlaceStore(std::size_t payload_floats, std::size_t record_floats, std::size_t value_floats)
      : payload_floats_(static_cast<int>(payload_floats)),
        value_floats_(static_cast<int>(value_floats)),
        arena_(record_floats) {}
  PlaceStore(std::size_t payload_floats, std::size_t record_floats)
      : PlaceStore(payload_floats, record_floats, record_floats) {}
  explicit PlaceStore(std::size_t payload_floats) : PlaceStore(payload_floats, payload_floats) {}
  int payload_floats_;
  int value_floats_;
  PayloadArena arena_;
};

std::unique_ptr<PlaceStore> make_scan_context_store(const ScanContextConfig& config,
                                                    PlaceStorage storage);
std::unique_ptr<PlaceStore> make_m2dp_store(int columns);
std::unique_ptr<PlaceStore> make_delight_store(int columns);
std::unique_ptr<PlaceStore> make_birds_eye_store(const BirdsEyePlaceConfig& place,
                                                 const BirdsEyeSearchConfig& search);

}  // namespace loopscan
