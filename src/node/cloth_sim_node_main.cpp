// cloth_sim_node: reads its parameters, loads the scene and serves until shut down.
#include <ros/package.h>
#include <ros/ros.h>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/names.h"
#include "cloth_sim/node/options.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, cloth_sim::node::names::kNode);
  ros::NodeHandle nh, pnh("~");
  try {
    XmlRpc::XmlRpcValue params;  // stays invalid (= no parameter) if the namespace is empty
    ros::param::get(pnh.getNamespace(), params);
    const cloth_sim::node::NodeOptions options = cloth_sim::node::parseNodeOptions(params);
    const std::string scene_dir = ros::package::getPath("cloth_sim") + "/config/scenes";
    const cloth_sim::SceneConfig scene = cloth_sim::node::loadScene(options, scene_dir);
    cloth_sim::node::ClothSimNode node(nh, pnh, options, scene.name,
                                       cloth_sim::node::buildScene(scene));
    ros::spin();  // one thread: see ClothSimNode
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", cloth_sim::node::names::kNode, e.what());
    return 1;
  }
  return 0;
}
