#pragma once
// The order in which the scanner visits the views (docs/registration.md): a motion
// cost between views, shortest paths over the view graph, and a tour that keeps each
// view after one it registers to.

#include <scanplan/core/view.h>
#include <scanplan/registration/registration.h>
#include <scanplan/scanner/simulation.h>

#include <Eigen/Core>

#include <span>
#include <vector>

namespace scanplan {

struct SequenceOptions {
  // A rotation of one radian counts as this much travel: about the length of the scanner
  // body, so that the cost bounds how far any point of the body moves.
  double rotation_arm = 200;  // mm
  double clearance = 100;     // mm above the part for moves that go over it
};

// The direct motion cost between every two views: the camera's straight travel plus the
// rotation between the two orientations times the arm. A straight path that crosses the
// part, a fixture or the working plane is replaced by one over the top: up to the
// clearance above the part, across, down.
Eigen::MatrixXd directCosts(const Simulator& simulator, std::span<const View> views,
                            const SequenceOptions& options = {});

// The same from each view of `from` (rows) to each of `to` (columns).
Eigen::MatrixXd directCosts(const Simulator& simulator, std::span<const View> from,
                            std::span<const View> to, const SequenceOptions& options = {});

// All-pairs shortest paths (Dijkstra from every view) over the complete graph of `direct`.
Eigen::MatrixXd shortestPaths(const Eigen::MatrixXd& direct);

// links[i][j] != 0 when view i may follow view j: they register to each other
// (Registration::linked), or either is registered by the robot or by reference points (in
// the cell's or the markers' frame, it may come anywhere), or i is registered by ICP and
// the scans are aligned once all are taken (Registration::aligned_as_taken false).
std::vector<std::vector<char>> registrationLinks(std::span<const View> views,
                                                 const Registration& registration);

// The length of an open path through nodes 0..k-1 of `cost`, for k = 1..n, built by
// cheapest insertion: each node in turn put where it lengthens the path least (between two
// nodes or at either end).
std::vector<double> insertionPathLengths(const Eigen::MatrixXd& cost);

// Length of the open path through `order` (indices into cost).
double pathLength(const Eigen::MatrixXd& cost, std::span<const int> order);

// Nearest-neighbour order of all nodes from `start`, each node taken, when one can be, among
// those that may follow a node already visited (linked[i][j] != 0: i may follow j); empty
// without nodes.
std::vector<int> nearestNeighbourOrder(const Eigen::MatrixXd& cost,
                                       const std::vector<std::vector<char>>& linked, int start);

// `order` improved by 2-opt moves (segment reversals; the start stays) that shorten the path
// and leave no node before every node it is linked to when it was not so already.
std::vector<int> twoOpt(const Eigen::MatrixXd& cost, const std::vector<std::vector<char>>& linked,
                        std::vector<int> order);

// `order` improved by or-opt moves: a run of one to three consecutive nodes taken out and
// put back, either way round, where that shortens the path most (the start stays), leaving
// no node before every node it is linked to when it was not so already.
std::vector<int> orOpt(const Eigen::MatrixXd& cost, const std::vector<std::vector<char>>& linked,
                       std::vector<int> order);

// `order` improved by 2-opt and or-opt in turn, until neither shortens it.
std::vector<int> improvedOrder(const Eigen::MatrixXd& cost,
                               const std::vector<std::vector<char>>& linked,
                               std::vector<int> order);

struct Sequence {
  std::vector<int> views;               // ids, in visiting order, from the reference view
  double length = 0;                    // motion cost along them, mm
  double nearest_neighbour_length = 0;  // of the nearest-neighbour order under the same rule
};

// The sequence of all views from the reference view, each registered view after one it
// registers to (linked): nearest neighbour under that rule, then improvedOrder; or the
// plain nearest-neighbour order improved so, when it breaks the rule no more and is
// shorter. Views that register to nothing come where the path passes them best.
Sequence sequenceViews(const Simulator& simulator, std::span<const View> views,
                       const Registration& registration, const SequenceOptions& options = {});

// The same over a given cost: the order chosen by `order_cost` (all-pairs, as
// shortestPaths gives), the lengths measured by `length_cost`, e.g. a robot's joint travel
// time for the order and the scanner's motion in mm for the lengths.
Sequence sequenceViews(const Eigen::MatrixXd& order_cost, const Eigen::MatrixXd& length_cost,
                       std::span<const View> views, const Registration& registration);

}  // namespace scanplan
