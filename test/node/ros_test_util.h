// Helpers shared by the node's rostests: a probe that collects what the node publishes, service
// calls, and reading the cloth back out of the markers.
#pragma once

#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <visualization_msgs/MarkerArray.h>

#include <cloth_sim/ClothState.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::test {

using node::toVec3;
namespace names = node::names;

/// Path of a file in the source tree.
std::string sourcePath(const std::string& relative);

/// Subscribes to cloth/markers, cloth/state and /rosout and keeps what arrives (callbacks run
/// on an AsyncSpinner started by the test's main, so waiting here never blocks them).
class NodeProbe {
 public:
  explicit NodeProbe(ros::NodeHandle nh);

  /// Waits until a state and a marker array arrived; false after @p timeout s.
  bool waitForTraffic(double timeout);
  /// The first state received after this call that satisfies @p pred, within @p timeout s.
  std::optional<ClothState> waitForState(const std::function<bool(const ClothState&)>& pred,
                                         double timeout);
  /// The first marker array received after this call that satisfies @p pred.
  std::optional<visualization_msgs::MarkerArray> waitForMarkers(
      const std::function<bool(const visualization_msgs::MarkerArray&)>& pred, double timeout);
  /// Every marker array received during the next @p seconds (wall time).
  std::vector<visualization_msgs::MarkerArray> collectMarkers(double seconds);
  /// Every state received during the next @p seconds.
  std::vector<ClothState> collectStates(double seconds);
  /// Every state received from now until the simulation has advanced @p sim_seconds (its own
  /// clock: on a busy machine the node steps slower than real time, and a physical event takes
  /// the same simulated time), or until @p wall_timeout s have passed.
  std::vector<ClothState> collectSimulatedTime(double sim_seconds, double wall_timeout = 60.0);
  /// True once a /rosout message containing @p text arrived (ever), within @p timeout s.
  bool waitForLog(const std::string& text, double timeout);
  /// How many /rosout messages so far contain @p text.
  int countLogs(const std::string& text);

  ClothState latestState();
  std::size_t markerCount();

 private:
  std::mutex mutex_;
  std::vector<ClothState> states_;  ///< since the last collect / wait (bounded)
  std::vector<visualization_msgs::MarkerArray> markers_;
  std::vector<std::string> logs_;
  std::optional<ClothState> latest_state_;
  std::size_t marker_count_ = 0;
  ros::Subscriber markers_sub_, state_sub_, log_sub_;
};

/// Calls service @p name (waiting up to 10 s for it); fails the test if the call itself fails.
template <class Service>
typename Service::Response call(const std::string& name, const typename Service::Request& req);

/// The cloth marker (ns "cloth", id 0) of @p array, or nullptr.
const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& array,
                                             const std::string& ns, int id);

/// Particle positions read back from the cloth TRIANGLE_LIST, using the scene's triangles
/// (point 3t + k is particle triangles(k, t)). Fails the test if the list does not have one
/// point per triangle corner, or gives one particle two different positions.
Points clothPositions(const visualization_msgs::MarkerArray& array,
                      const Eigen::Matrix3Xi& triangles, int particle_count);

/// True when every number of every marker of @p array is finite.
bool allFinite(const visualization_msgs::MarkerArray& array);

/// Waits until @p pub has a subscriber (a message published before that is lost); false after
/// @p timeout s.
bool waitForSubscriber(const ros::Publisher& pub, double timeout = 10.0);

/// A point stamped in @p frame.
geometry_msgs::PointStamped stamped(const std::string& frame, double x, double y, double z);

/// Runs cloth_sim_node at @p executable with command-line @p args for at most @p seconds
/// (timeout(1)); its exit status (124: still running when stopped) and its output.
std::pair<int, std::string> runNodeProcess(const std::string& executable, const std::string& args,
                                           double seconds);

/// ros::init, an AsyncSpinner, RUN_ALL_TESTS: the main of every node rostest.
int runRosTests(int argc, char** argv, const char* node_name);

}  // namespace cloth_sim::test

#include "ros_test_util_impl.h"
