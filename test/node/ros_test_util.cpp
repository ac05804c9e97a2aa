#include "ros_test_util.h"

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <thread>

namespace cloth_sim::test {
namespace {

constexpr std::size_t kKeep = 2000;  ///< messages kept per topic between two reads

template <class T>
void keep(std::vector<T>& v, const T& msg) {
  if (v.size() >= kKeep) v.erase(v.begin(), v.begin() + kKeep / 2);
  v.push_back(msg);
}

void sleepABit() { std::this_thread::sleep_for(std::chrono::milliseconds(5)); }

/// The first message that arrives in @p buffer (emptied first) and satisfies @p pred.
template <class T>
std::optional<T> waitFor(std::mutex& mutex, std::vector<T>& buffer,
                         const std::function<bool(const T&)>& pred, double timeout) {
  {
    std::lock_guard<std::mutex> lock(mutex);
    buffer.clear();
  }
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::WallTime::now() < end) {
    std::vector<T> got;
    {
      std::lock_guard<std::mutex> lock(mutex);
      got.swap(buffer);
    }
    for (const T& m : got) {
      if (pred(m)) return m;
    }
    sleepABit();
  }
  return std::nullopt;
}

/// Every message that arrives in @p buffer (emptied first) during @p seconds.
template <class T>
std::vector<T> collect(std::mutex& mutex, std::vector<T>& buffer, double seconds) {
  {
    std::lock_guard<std::mutex> lock(mutex);
    buffer.clear();
  }
  ros::WallDuration(seconds).sleep();
  std::lock_guard<std::mutex> lock(mutex);
  std::vector<T> out;
  out.swap(buffer);
  return out;
}

bool finite(const geometry_msgs::Point& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace

std::string sourcePath(const std::string& relative) {
  return std::string(CLOTH_SIM_SOURCE_DIR) + "/" + relative;
}

NodeProbe::NodeProbe(ros::NodeHandle nh) {
  markers_sub_ = nh.subscribe<visualization_msgs::MarkerArray>(
      names::kMarkers, 100, [this](const visualization_msgs::MarkerArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex_);
        keep(markers_, *m);
        ++marker_count_;
      });
  state_sub_ = nh.subscribe<ClothState>(names::kState, 500, [this](const ClothState::ConstPtr& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    keep(states_, *s);
    latest_state_ = *s;
  });
  log_sub_ = nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000,
                                              [this](const rosgraph_msgs::Log::ConstPtr& l) {
                                                std::lock_guard<std::mutex> lock(mutex_);
                                                logs_.push_back(l->msg);
                                              });
}

bool NodeProbe::waitForTraffic(double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (latest_state_ && marker_count_ > 0) return true;
    }
    sleepABit();
  }
  return false;
}

std::optional<ClothState> NodeProbe::waitForState(
    const std::function<bool(const ClothState&)>& pred, double timeout) {
  return waitFor(mutex_, states_, pred, timeout);
}

std::optional<visualization_msgs::MarkerArray> NodeProbe::waitForMarkers(
    const std::function<bool(const visualization_msgs::MarkerArray&)>& pred, double timeout) {
  return waitFor(mutex_, markers_, pred, timeout);
}

std::vector<visualization_msgs::MarkerArray> NodeProbe::collectMarkers(double seconds) {
  return collect(mutex_, markers_, seconds);
}

std::vector<ClothState> NodeProbe::collectStates(double seconds) {
  return collect(mutex_, states_, seconds);
}

std::vector<ClothState> NodeProbe::collectSimulatedTime(double sim_seconds, double wall_timeout) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    states_.clear();
  }
  std::vector<ClothState> out;
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(wall_timeout);
  while (ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      out.insert(out.end(), states_.begin(), states_.end());
      states_.clear();
    }
    if (!out.empty() && out.back().sim_time - out.front().sim_time >= sim_seconds) break;
    sleepABit();
  }
  return out;
}

bool NodeProbe::waitForLog(const std::string& text, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::WallTime::now() < end) {
    if (countLogs(text) > 0) return true;
    sleepABit();
  }
  return false;
}

int NodeProbe::countLogs(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  int n = 0;
  for (const std::string& l : logs_) n += l.find(text) != std::string::npos ? 1 : 0;
  return n;
}

ClothState NodeProbe::latestState() {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_state_.value_or(ClothState());
}

std::size_t NodeProbe::markerCount() {
  std::lock_guard<std::mutex> lock(mutex_);
  return marker_count_;
}

const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& array,
                                             const std::string& ns, int id) {
  for (const auto& m : array.markers) {
    if (m.ns == ns && m.id == id) return &m;
  }
  return nullptr;
}

Points clothPositions(const visualization_msgs::MarkerArray& array,
                      const Eigen::Matrix3Xi& triangles, int particle_count) {
  Points x = Points::Constant(3, particle_count, std::nan(""));
  const visualization_msgs::Marker* cloth = findMarker(array, names::kClothNs, 0);
  if (cloth == nullptr) {
    ADD_FAILURE() << "no cloth marker";
    return x;
  }
  if (cloth->points.size() != static_cast<std::size_t>(3 * triangles.cols())) {
    ADD_FAILURE() << cloth->points.size() << " cloth points for " << triangles.cols()
                  << " triangles";
    return x;
  }
  int conflicts = 0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto& p = cloth->points[3 * t + k];
      const Vec3 v(p.x, p.y, p.z);
      auto col = x.col(triangles(k, t));
      if (std::isnan(col.x())) col = v;
      else if (col != v) ++conflicts;
    }
  }
  EXPECT_EQ(conflicts, 0) << "a particle drawn at two places";
  return x;
}

bool allFinite(const visualization_msgs::MarkerArray& array) {
  for (const auto& m : array.markers) {
    if (!finite(m.pose.position) || !std::isfinite(m.scale.x) || !std::isfinite(m.scale.y) ||
        !std::isfinite(m.scale.z)) {
      return false;
    }
    for (const auto& p : m.points) {
      if (!finite(p)) return false;
    }
  }
  return true;
}

bool waitForSubscriber(const ros::Publisher& pub, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (pub.getNumSubscribers() == 0) {
    if (ros::WallTime::now() > end) return false;
    ros::WallDuration(0.01).sleep();
  }
  return true;
}

geometry_msgs::PointStamped stamped(const std::string& frame, double x, double y, double z) {
  geometry_msgs::PointStamped p;
  p.header.frame_id = frame;
  p.header.stamp = ros::Time(0);
  p.point.x = x;
  p.point.y = y;
  p.point.z = z;
  return p;
}

int runRosTests(int argc, char** argv, const char* node_name) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}

std::pair<int, std::string> runNodeProcess(const std::string& executable, const std::string& args,
                                           double seconds) {
  char limit[32];
  std::snprintf(limit, sizeof limit, "%g", seconds);
  const std::string cmd = std::string("timeout ") + limit + " " + executable + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, pipe) != nullptr) out += buf;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

}  // namespace cloth_sim::test
