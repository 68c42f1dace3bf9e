// The place database from 10^3 to 10^6 places (one thread), Scan Context (default) or the
// bird's-eye place (--method bev: its indexed query ranks every place's key, as the exact one
// does), against Scan Context's own ring-key tree search (scan_context_tree.hpp) on Scan
// Contexts of the same places.
//   build/bench/loopscan_bench_db_scale [--sizes 1000,10000,100000,1000000] [--method sc|bev]
//       [--maps perturbed,sessions] [--storage compact|full] [--queries 100]
//       [--oracle-max 1000000] [--baseline-oracle-max 100000]
//       [--candidates N] [--pool F] [--stats N] [--refine N]   (QueryOptions of the queries)
// Maps: `perturbed` = the simulated city in summer (world 7, session 100, 977 places) plus
// perturbed copies of it (each cell x (1 + 0.1 N(0,1)), 10% of cells emptied, a random sector
// roll; bird's-eye places: the place's image as points, each cell's count scaled the same way,
// turned by a random yaw and moved up to 3 m, described again); `sessions` = 8 simulated sessions
// of the same world (4 summer, 4 winter) plus perturbed copies of them. Queries: another summer
// drive (session 102), the ones with a true place (a map place within 10 m). Per size: build
// seconds (cumulative), bytes per place (Database::memory_bytes), CPU ms per indexed query (k = 5),
// top-1 agreement with exact search over the same places (and whether it is a copy of the same base
// place as exact's), true-place rate of top-1 (within 10 m); for Scan Context's search: ms per
// query, true-place rate, agreement with its own brute force.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/descriptors/birds_eye_place.hpp"
#include "loopscan/sim/simulated_places.hpp"
#include "perturbed_signature.hpp"
#include "scan_context_tree.hpp"

namespace loopscan {
namespace {

// Query times are the thread's CPU time (the machine is shared; wall time would count the
// other jobs' time slices), build times wall time.
double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<long> numbers(const std::string& s) {
  std::vector<long> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stol(item));
  return out;
}

struct Base {
  std::vector<PlaceDescriptor> places;         // the benchmarked method's
  std::vector<PlaceDescriptor> scan_contexts;  // for Scan Context's tree
  std::vector<Eigen::Vector3d> positions;
  void append(const sim::SimulatedPlaces& p, const sim::SimulatedPlaces& sc) {
    if (p.keyframe_ids != sc.keyframe_ids) {
      throw std::runtime_error("the two methods described different keyframes");
    }
    places.insert(places.end(), p.places.begin(), p.places.end());
    scan_contexts.insert(scan_contexts.end(), sc.places.begin(), sc.places.end());
    const auto pos = p.positions();
    positions.insert(positions.end(), pos.begin(), pos.end());
  }
};

// A perturbed copy of a bird's-eye place: its image as points (a cell of value v holds
// (v / 16)^2 structure points, each count scaled by 1 + 0.1 N(0,1), 10 % of cells emptied),
// turned by a random yaw and moved up to 3 m in x and z, then described again.
Signature perturbed_birds_eye(const Signature& s, const BirdsEyeDescriber& describer,
                              std::mt19937& rng) {
  const BirdsEyePlaceConfig& c = describer.config();
  const BirdsEyePlace place = birds_eye_place(s, c);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double yaw = 2 * M_PI * u(rng), dx = 6 * u(rng) - 3, dz = 6 * u(rng) - 3;
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  std::vector<float> x, y, z;
  for (int row = 0; row < place.side; ++row) {
    for (int col = 0; col < place.side; ++col) {
      const double v = place.image[std::size_t(row) * place.side + col];
      if (v == 0 || u(rng) < 0.1) continue;
      const long count = std::lround((v / 16) * (v / 16) * std::max(0.0, 1 + 0.1 * n01(rng)));
      const double px = -c.range_m + (col + 0.5) * c.cell_m,
                   pz = -c.range_m + (row + 0.5) * c.cell_m;
      for (long k = 0; k < count; ++k) {
        x.push_back(float(cy * px - sy * pz + dx));
        y.push_back(-2.0f);  // 2 m over the camera: structure
        z.push_back(float(sy * px + cy * pz + dz));
      }
    }
  }
  return birds_eye_signature(describer.describe(x.data(), y.data(), z.data(), x.size()));
}

struct Options {
  Method method = Method::ScanContext;
  std::vector<long> sizes{1000, 10000, 100000, 1000000};
  std::vector<std::string> maps{"perturbed", "sessions"};
  PlaceStorage storage = PlaceStorage::Compact;
  int queries = 100;
  long oracle_max = 1000000, baseline_oracle_max = 100000;
  QueryOptions indexed;  // --candidates, --pool, --stats, --refine override its defaults
};

void run_map(const std::string& kind, const Options& opt, const sim::Trajectory& route,
             const sim::SimulatedPlaces& query_session, const sim::SimulatedPlaces& query_sc) {
  Base base;
  const auto describe = [&](sim::Season season, unsigned session) {
    const auto sc = sim::simulate_places(route, season, 7, session, Method::ScanContext, 2);
    base.append(opt.method == Method::ScanContext
                    ? sc
                    : sim::simulate_places(route, season, 7, session, opt.method, 2),
                sc);
  };
  if (kind == "perturbed") {
    describe(sim::Season::Summer, 100);
  } else {
    for (unsigned s = 0; s < 8; ++s)
      describe(s % 2 ? sim::Season::Winter : sim::Season::Summer, 110 + s);
  }
  // Queries with a true place in the base map.
  std::vector<std::size_t> queries;
  const auto qpos = query_session.positions();
  for (std::size_t i = 0; i < qpos.size(); ++i) {
    for (const auto& p : base.positions) {
      if ((p - qpos[i]).norm() <= 10.0) {
        queries.push_back(i);
        break;
      }
    }
  }
  const std::size_t step = std::max<std::size_t>(1, queries.size() / opt.queries);
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < queries.size() && chosen.size() < std::size_t(opt.queries); i += step)
    chosen.push_back(queries[i]);

  DatabaseConfig cfg;
  cfg.method = opt.method;
  // Compact storage is Scan Context's (bird's-eye places are bytes already).
  cfg.storage = opt.method == Method::ScanContext ? opt.storage : PlaceStorage::Full;
  const BirdsEyeDescriber birds_eye(cfg.birds_eye);
  Database db(cfg);
  bench::ScanContextTree sc(20, 60);
  std::vector<std::size_t> origin;  // base place of every map place
  std::mt19937 rng(42);
  double build_s = 0, sc_build_s = 0;
  std::printf(
      "| map | places | build s | bytes/place | ms/query | top-1 = exact | same place as exact | "
      "true place | SC tree ms/query | SC true place | SC tree = SC brute force | SC bytes/place "
      "|\n");
  std::printf(
      "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (long n : opt.sizes) {
    std::vector<Signature> added;
    while (static_cast<long>(db.size()) < n) {
      const std::size_t i = db.size(), j = i % base.places.size();
      PlaceDescriptor d = base.places[j], sc_place = base.scan_contexts[j];
      d.signature = Signature(d.signature.topRows(1));
      sc_place.signature = Signature(sc_place.signature.topRows(1));
      if (i >= base.places.size()) {
        d.signature = opt.method == Method::BirdsEye
                          ? perturbed_birds_eye(d.signature, birds_eye, rng)
                          : bench::perturbed(opt.method, d.signature, rng);
        sc_place.signature = bench::perturbed(Method::ScanContext, sc_place.signature, rng);
      }
      double t0 = now_s();
      db.add({0, static_cast<int>(i)}, d);
      build_s += now_s() - t0;
      t0 = now_s();
      sc.add(sc_place.signature);
      sc_build_s += now_s() - t0;
      origin.push_back(j);
    }
    double t0 = now_s();
    sc.build();
    sc_build_s += now_s() - t0;
    const auto& qp = query_session.places;
    const auto& qsc = query_sc.places;
    const QueryOptions& indexed = opt.indexed;
    QueryOptions exact;
    exact.retrieval = Retrieval::Exact;
    t0 = cpu_s();
    int nq = 0;
    for (int rep = 0; rep < 3; ++rep)
      for (std::size_t q : chosen) db.query(qp[q], 5, indexed), ++nq;
    const double ms = 1e3 * (cpu_s() - t0) / nq;
    t0 = cpu_s();
    for (int rep = 0; rep < 3; ++rep)
      for (std::size_t q : chosen) sc.query(qsc[q].signature);
    const double sc_ms = 1e3 * (cpu_s() - t0) / nq;
    int agree = 0, same_place = 0, oracle_n = 0, truth = 0, sc_truth = 0, sc_agree = 0,
        sc_oracle_n = 0;
    auto true_place = [&](std::size_t q, std::size_t i) {
      return (base.positions[origin[i]] - qpos[q]).norm() <= 10.0;
    };
    for (std::size_t q : chosen) {
      const auto b = db.query(qp[q], 1, indexed);
      truth += !b.empty() && true_place(q, b[0].index);
      const auto s = sc.query(qsc[q].signature);
      sc_truth += true_place(q, s.first);
      if (n <= opt.oracle_max) {
        const auto a = db.query(qp[q], 1, exact);
        agree += !a.empty() && !b.empty() && a[0].index == b[0].index;
        // A copy of the same base place (copies are near-identical, see the header).
        same_place += !a.empty() && !b.empty() && origin[a[0].index] == origin[b[0].index];
        ++oracle_n;
      }
      if (n <= opt.baseline_oracle_max) {
        sc_agree += sc.brute_force(qsc[q].signature).first == s.first;
        ++sc_oracle_n;
      }
    }
    auto share = [](int k, int total) {
      char b[32];
      if (total == 0) return std::string("n/a");
      std::snprintf(b, sizeof b, "%.3f", double(k) / total);
      return std::string(b);
    };
    std::printf("| %s | %ld | %.1f | %.0f | %.3f | %s | %s | %s | %.3f | %s | %s | %.0f |\n",
                kind.c_str(), n, build_s, double(db.memory_bytes()) / n, ms,
                share(agree, oracle_n).c_str(), share(same_place, oracle_n).c_str(),
                share(truth, int(chosen.size())).c_str(), sc_ms,
                share(sc_truth, int(chosen.size())).c_str(), share(sc_agree, sc_oracle_n).c_str(),
                double(sc.memory_bytes()) / n);
    std::fflush(stdout);
  }
  std::printf("(%zu queries with a true place; SC tree build %.1f s)\n\n", chosen.size(),
              sc_build_s);
}

}  // namespace
}  // namespace loopscan

int main(int argc, char** argv) {
  using namespace loopscan;
  Options opt;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--sizes")
      opt.sizes = numbers(v);
    else if (a == "--method")
      opt.method = v == "bev" ? Method::BirdsEye : Method::ScanContext;
    else if (a == "--maps") {
      opt.maps.clear();
      std::stringstream in(v);
      for (std::string m; std::getline(in, m, ',');) opt.maps.push_back(m);
    } else if (a == "--storage")
      opt.storage = v == "full" ? PlaceStorage::Full : PlaceStorage::Compact;
    else if (a == "--queries")
      opt.queries = std::stoi(v);
    else if (a == "--candidates")
      opt.indexed.candidates = std::stoi(v);
    else if (a == "--pool")
      opt.indexed.index_pool_factor = std::stoi(v);
    else if (a == "--stats")
      opt.indexed.stats_sample = std::stoi(v);
    else if (a == "--refine")
      opt.indexed.refine = std::stoi(v);
    else if (a == "--oracle-max")
      opt.oracle_max = std::stol(v);
    else if (a == "--baseline-oracle-max")
      opt.baseline_oracle_max = std::stol(v);
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const sim::Trajectory route = sim::make_builtin_trajectory("city");
  const auto sc_queries =
      sim::simulate_places(route, sim::Season::Summer, 7, 102, Method::ScanContext, 2);
  const auto queries =
      opt.method == Method::ScanContext
          ? sc_queries
          : sim::simulate_places(route, sim::Season::Summer, 7, 102, opt.method, 2);
  std::printf("method: %s, storage: %s\n\n", method_name(opt.method).c_str(),
              opt.method == Method::ScanContext && opt.storage == PlaceStorage::Compact ? "compact"
                                                                                        : "full");
  for (const std::string& m : opt.maps) loopscan::run_map(m, opt, route, queries, sc_queries);
}
