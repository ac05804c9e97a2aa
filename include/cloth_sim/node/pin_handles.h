/// @file pin_handles.h
/// RViz drag handles on pins (interactive_markers): a person moves a pin with the mouse.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <geometry_msgs/PointStamped.h>
#include <interactive_markers/interactive_marker_server.h>
#include <visualization_msgs/InteractiveMarker.h>

#include "cloth_sim/core/model/pins.h"

namespace cloth_sim::node {

/// Name of the handle of pin @p pin_id: "pin_<id>".
std::string pinHandleName(int pin_id);
/// The pin id in a handle name, or -1 if @p name is not one.
int pinIdFromHandleName(const std::string& name);

/// Handle size (m across) for a cloth of @p cloth_size m (the largest side of its bounding box):
/// a tenth of it, within [0.02, 0.5] m, so that a handle neither buries a 1 m cloth (0.2 m
/// handles did) nor vanishes on a large one.
double handleSizeFor(double cloth_size);

/// The handle of one pin, centred on its target (m, in @p frame_id), @p scale m across:
/// a sphere dragged freely in the view plane (MOVE_3D), arrows along x, y and z (MOVE_AXIS)
/// and a disc for the horizontal plane (MOVE_PLANE, normal z). Visuals are filled in
/// (interactive_markers::autoComplete), so the message is complete as built.
visualization_msgs::InteractiveMarker makePinHandle(int pin_id, const Vec3& target,
                                                    const std::string& frame_id, double scale);

/// Keeps one handle per pin on an InteractiveMarkerServer and reports drags.
///
/// Runs on the caller's callback queue (no thread of its own), so drags are serialized with
/// everything else the node does.
class PinHandles {
 public:
  /// Called when a handle is dragged: the pin id and the new target (the handle's frame).
  using MoveCallback = std::function<void(int pin_id, const geometry_msgs::PointStamped& target)>;

  /// Serves handles on <topic_ns>/update etc. At most @p max_handles pins get handles: with
  /// more pins than that, none has one (see NodeOptions::max_interactive_pins). Each handle is
  /// @p handle_size m across (handleSizeFor: scaled to the cloth).
  PinHandles(const std::string& topic_ns, std::string frame_id, int max_handles,
             MoveCallback on_move, double handle_size = 0.2);

  /// Adds, removes and moves handles to match @p pins; publishes only when something changed.
  void sync(const std::vector<Pin>& pins);

 private:
  void onFeedback(const visualization_msgs::InteractiveMarkerFeedbackConstPtr& feedback);

  interactive_markers::InteractiveMarkerServer server_;
  std::string frame_id_;
  double handle_size_;  ///< m across
  int max_handles_;
  MoveCallback on_move_;
  std::map<int, Vec3> shown_;  ///< pin id -> pose the server holds for its handle
  /// A drag arrived since the last sync: the server holds its pose but sends it to the other
  /// clients (a second RViz) only on applyChanges().
  bool dragged_ = false;
  bool over_limit_ = false;
};

}  // namespace cloth_sim::node
