// The place database at 1k, 10k and 100k places, per method, exact and indexed (one thread).
// Places: the simulated city in summer (world seed 7, ~1,000 keyframes), then perturbed copies
// of them (each cell scaled by 1 + 0.1 N(0,1), 10% of the cells emptied, a random sector roll
// for Scan Context) up to the size. Queries: another summer drive through the same world
// (other parked cars, other VO noise), so every query has a true place in the map.
//   build/bench/loopscan_bench_db [--benchmark_filter=...]
// Counters: per_item = seconds per query (k = 5); bytes_per_place = heap growth of building
// the database / places; top1_agree = share of queries (100) whose indexed best place is
// the exact best place (NO_AGREE=1 skips it: it runs 100 exact queries per size).
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <random>

#include "loopscan/core/database/database.hpp"
#include "loopscan/sim/simulated_places.hpp"
#include "perturbed_signature.hpp"

namespace loopscan {
namespace {

struct Sessions {
  sim::SimulatedPlaces map, queries;
};

const Sessions& sessions(Method m) {
  static std::map<Method, Sessions> cache;
  auto it = cache.find(m);
  if (it == cache.end()) {
    const sim::Trajectory route = sim::make_builtin_trajectory("city");
    Sessions s{sim::simulate_places(route, sim::Season::Summer, 7, 100, m, 2),
               sim::simulate_places(route, sim::Season::Summer, 7, 102, m, 2)};
    it = cache.emplace(m, std::move(s)).first;
  }
  return it->second;
}

struct Built {
  std::unique_ptr<Database> db;
  double bytes_per_place = 0;
  double top1_agree = -1;
};

Built& built(Method m, std::size_t n) {
  static std::map<std::pair<Method, std::size_t>, Built> cache;
  auto key = std::make_pair(m, n);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const auto& base = sessions(m).map;
  Built b;
  const std::size_t heap0 = mallinfo2().uordblks;
  DatabaseConfig cfg;
  cfg.method = m;
  b.db = std::make_unique<Database>(cfg);
  std::mt19937 rng(static_cast<unsigned>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = i % base.places.size();
    if (i < base.places.size()) {
      b.db->add({0, static_cast<int>(i)}, base.places[j]);
    } else {
      b.db->add({0, static_cast<int>(i)}, {bench::perturbed(m, base.places[j].signature, rng)});
    }
  }
  b.bytes_per_place = double(mallinfo2().uordblks - heap0) / double(n);
  return cache.emplace(key, std::move(b)).first->second;
}

double top1_agreement(Method m, const Database& db) {
  const auto& q = sessions(m).queries.places;
  QueryOptions exact, indexed;
  exact.retrieval = Retrieval::Exact;
  int agree = 0, total = 0;
  for (std::size_t i = 0; i < q.size() && total < 200;
       i += std::max<std::size_t>(1, q.size() / 200)) {
    const auto a = db.query(q[i], 1, exact), b = db.query(q[i], 1, indexed);
    agree += !a.empty() && !b.empty() && a[0].index == b[0].index;
    ++total;
  }
  return double(agree) / total;
}

void BM_DatabaseQuery(benchmark::State& state) {
  const auto m = static_cast<Method>(state.range(0));
  const auto retrieval = static_cast<Retrieval>(state.range(1));
  const auto n = static_cast<std::size_t>(state.range(2));
  Built& b = built(m, n);
  QueryOptions opt;
  opt.retrieval = retrieval;
  opt.threads = static_cast<int>(state.range(3));
  const auto& queries = sessions(m).queries.places;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(b.db->query(queries[i++ % queries.size()], 5, opt).data());
  }
  state.counters["per_item"] =
      benchmark::Counter(static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["bytes_per_place"] = b.bytes_per_place;
  if (retrieval == Retrieval::Indexed) {
    if (b.top1_agree < 0 && !std::getenv("NO_AGREE")) b.top1_agree = top1_agreement(m, *b.db);
    state.counters["top1_agree"] = b.top1_agree;
  }
}

constexpr int kExact = static_cast<int>(Retrieval::Exact);
constexpr int kIndexed = static_cast<int>(Retrieval::Indexed);

void database_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"method", "indexed", "places", "threads"});
  for (int m : {0, 1, 2}) {
    for (int n : {1000, 10000, 100000}) {
      b->Args({m, kIndexed, n, 1});
      b->Args({m, kExact, n, 1});
      if (m == 0) b->Args({m, kExact, n, 2});  // exact search on both cores
    }
  }
}

BENCHMARK(BM_DatabaseQuery)
    ->Apply(database_args)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5)
    ->UseRealTime();  // wall time: the threads:2 runs use a second core

}  // namespace
}  // namespace loopscan

BENCHMARK_MAIN();
