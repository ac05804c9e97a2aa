// Template part of ros_test_util.h.
#pragma once

#include <gtest/gtest.h>

namespace cloth_sim::test {

template <class Service>
typename Service::Response call(const std::string& name, const typename Service::Request& req) {
  Service srv;
  srv.request = req;
  EXPECT_TRUE(ros::service::waitForService(name, ros::Duration(10.0))) << name << " not up";
  EXPECT_TRUE(ros::service::call(name, srv)) << "call to " << name << " failed";
  return srv.response;
}

}  // namespace cloth_sim::test
