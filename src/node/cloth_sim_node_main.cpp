// cloth_sim_node: reads its parameters, loads the scene and serves until shut down.
#include <ros/package.h>
#include <ros/ros.h>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/names.h"
#include "cloth_sim/node/options.h"
#include "cloth_sim/node/urdf_colliders.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, cloth_sim::node::names::kNode);
  ros::NodeHandle nh, pnh("~");
  try {
    XmlRpc::XmlRpcValue params;  // stays invalid (= no parameter) if the namespace is empty
    ros::param::get(pnh.getNamespace(), params);
    const cloth_sim::node::NodeOptions options = cloth_sim::node::parseNodeOptions(params);
    const std::string scene_dir = ros::package::getPath("cloth_sim") + "/config/scenes";
    cloth_sim::SceneConfig scene = cloth_sim::node::loadScene(options, scene_dir);
    if (!options.robot_links.empty()) {  // the robot's links join the scene's bodies
      std::string urdf = options.robot_description;
      if (urdf.empty() && !nh.getParam("robot_description", urdf)) {
        throw std::invalid_argument(
            "parameter '~robot_links': set, but neither ~robot_description nor robot_description "
            "holds a URDF");
      }
      try {
        for (cloth_sim::BodyCollider& b : cloth_sim::node::urdfColliders(
                 urdf, options.robot_links, options.robot_margin, options.robot_friction,
                 cloth_sim::node::resolveMeshUrl)) {
          scene.bodies.push_back(std::move(b));
        }
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("parameter '~robot_links': ") + e.what());
      }
    }
    cloth_sim::node::ClothSimNode node(nh, pnh, options, scene.name,
                                       cloth_sim::node::buildScene(scene));
    ros::spin();  // one thread: see ClothSimNode
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", cloth_sim::node::names::kNode, e.what());
    return 1;
  }
  return 0;
}
