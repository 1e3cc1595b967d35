#pragma once
// The registration graph (docs/registration.md): the views, the checks of their pairs, and a
// spanning forest of registrable pairs, each ICP pair verified before it is used, which
// decides the views that register; each registers along its chain of least error.
// Planning's bridging grows it view by view (planning/bridging.h).

#include "registration/overlaps.h"

#include <scanplan/core/disjoint_sets.h>
#include <scanplan/core/progress.h>
#include <scanplan/registration/registration.h>

#include <map>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace scanplan::detail {

struct IcpMemo;  // the ICP clouds and checks made so far, by view

class RegistrationGraph {
 public:
  RegistrationGraph(const Simulator& simulator, const RegistrationOptions& options,
                    const std::vector<Marker>& markers, const Progress& progress);

  std::vector<Observation> observe(std::span<const View> views) const;
  PairCheck check(const View& a, const Observation& oa, const View& b, const Observation& ob) const;

  // Adds views and the checks of their pairs with every view before them; then joins the
  // components by the new pairs (markers first, then the most stable, verified lazily).
  void add(std::span<const View> views);

  // The two sides a bridge joins: the main component and the one it is bridged towards,
  // their views and surface points, and how far every surface point is from each.
  struct Sides {
    std::vector<char> in_main, in_other;  // per view
    std::vector<Vec3> main_points, other_points;
    std::vector<double> to_main, to_other;  // per surface point
    double gap = 0;                         // from the main component's points to the other's
  };
  Sides sidesOf(int towards);

  // Adds `view`, which measures `seen`, when its pair with the view at index `partner`
  // registers (verified), and joins components by its pairs: true. Else the graph stays as
  // it was: false.
  bool addJoined(const View& view, const Observation& seen, std::size_t partner);

  std::size_t components();
  // The root of the component of the views seeing the reference points, if any; else of the
  // largest component (ties: the one with the earliest view).
  int mainComponent();
  // The roots of the components other than the main one that hold a view something
  // could register to.
  std::vector<int> bridgeable();

  // The registration of each view: a tree rooted at the reference view (or at the views
  // seeing the reference points), each view linked to it by the chain of pairs that link
  // (registration.links) whose errors add up least. Views from `first_bridge` on are
  // bridging views.
  Registration result(std::size_t first_bridge);

  const Simulator& simulator() const { return simulator_; }
  const std::vector<View>& views() const { return views_; }
  const std::vector<Observation>& observations() const { return seen_; }  // per view
  const std::vector<SurfacePoint>& points() const { return points_; }     // of the overlaps
  double spacing() const { return spacing_; }

 private:
  // Verifies the pair (when verification is on and it is an ICP pair).
  bool verify(std::size_t p);
  // Whether pair `a` is tried before pair `b` to join components: markers before ICP, more
  // shared markers, a better conditioned overlap.
  bool surer(std::size_t a, std::size_t b) const;
  // The mean square, mm², of the displacement pair `p`'s registration error gives a point
  // half the field's diagonal from where it holds: by markers, the rigid fit of the shared
  // markers under the marker noise (each position measured in both views); by ICP, the
  // check's own error (the tolerance when not checked).
  double linkVariance(std::size_t p) const;
  // Per view the `roots` reach by pairs that link (in `registration`), the pair it
  // registers by: the chain of least summed linkVariance (Dijkstra), as a chain's errors add.
  std::map<std::size_t, std::size_t> leastErrorLinks(const Registration& registration,
                                                     const std::vector<std::size_t>& roots) const;
  int find(int v);
  // Stores the view and the checks of its pairs with every view before it; returns the
  // indices of those pairs.
  std::vector<std::size_t> insert(const View& view, const Observation& seen);
  // Distance from each surface point to the nearest of `to`.
  std::vector<double> distances(const std::vector<Vec3>& to) const;
  // Joins components by the `candidates` pairs, in the manner of Kruskal's algorithm;
  // `shown`: with progress (the share of the registrable pairs walked).
  void connect(std::vector<std::size_t> candidates, bool shown = false);
  // Runs the ICP checks of the next few candidates from `first` that would join two
  // components as things stand, in parallel; returns the index after the last one looked
  // at. Some may turn out not to be needed once an earlier one joins their components;
  // the tree is the same as with one check at a time. Six checks a core: with fewer, a
  // core waits idle behind the longest check of a batch.
  std::size_t verifyAhead(const std::vector<std::size_t>& candidates, std::size_t first);
  // The ICP clouds of the views of `pairs` not made before, in parallel.
  void makeClouds(const std::vector<std::size_t>& pairs);
  // The ICP checks of `pairs`, in parallel; pairs checked before (as the same views) are not
  // checked again, and the clouds of the others' views are made once each.
  void registerPairs(const std::vector<std::size_t>& pairs);

  const Simulator& simulator_;
  const RegistrationOptions& options_;
  const Progress& progress_;
  std::shared_ptr<const detail::Overlaps> overlaps_;  // shared by the copies of a graph
  const std::vector<SurfacePoint>& points_;
  double spacing_ = 0;
  std::vector<View> views_;
  std::vector<Observation> seen_;
  std::vector<PairCheck> pairs_;
  std::vector<std::pair<std::size_t, std::size_t>> ends_;  // view indices of each pair
  DisjointSets sets_;                                      // of view indices, by pairs used
  std::vector<char> constrained_;  // per view: something could register to it
  std::vector<char> framed_;       // per view: registers by the reference points it sees
  int frame_ = -1;                 // the first view that does, if any
  std::shared_ptr<IcpMemo> memo_;
  // The last main component (per view: in it) and each surface point's distance from it,
  // the same for every component bridged towards until a bridge joins one.
  std::pair<std::vector<char>, std::vector<double>> to_main_;
};

// The method a registration uses: the options', or by default Markers where there are
// markers, else Geometry.
RegistrationMode registrationMethod(const RegistrationOptions& options,
                                    const std::vector<Marker>& markers);

// The graph of `views` (options validated; with Geometry, the markers are not used): their
// pairs checked and joined, as registerViews and planning's bridging begin.
RegistrationGraph graphOf(const Simulator& simulator, std::span<const View> views,
                          const std::vector<Marker>& markers, const RegistrationOptions& options,
                          const Progress& progress);

// The graph's registration: its views' (those from `first_bridge` on bridging views) with
// the method, the markers counted and, with a robot accurate enough, every view registered
// by the robot.
Registration finishRegistration(RegistrationGraph& graph, std::size_t first_bridge,
                                RegistrationMode method, const std::vector<Marker>& markers,
                                const RegistrationOptions& options);

}  // namespace scanplan::detail
