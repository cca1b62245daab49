// vdtnav bag play BAG: a ROS 1 or ROS 2 bag published onto a ROS 2 graph over DDS with ROS 2's
// conventions (vdtnav::ros2::play_bag), and optionally a map as map_server would: what a user
// without ROS 2's tools needs to try vdtnav_ros2_localizer.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "common.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros2/bag_player.hpp"
#include "vdtnav/ros2/dds.hpp"

namespace vdtnav::tools {

namespace {

struct PlayArgs {
  std::string bag, map, map_topic = "/map";
  std::vector<std::string> topics;
  double rate = 1.0, wait = 0.0;
  int domain = -1;
  bool loopback = false;
};

void run_bag_play(const PlayArgs& a) {
  const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(a.bag);
  ros2::ParticipantOptions po;
  po.name = "vdtnav_bag_play";
  po.domain = a.domain;
  if (a.loopback) po.network = ros2::ParticipantOptions::Network::kLoopback;
  ros2::Participant participant(po);
  ros2::PlayOptions play;
  play.rate = a.rate;
  play.topics = a.topics;
  play.wait_for_readers = a.wait;
  play.map_topic = a.map_topic;
  if (!a.map.empty()) play.map = load_ros_map(a.map);
  std::fprintf(stderr, "[bag play] %s on DDS domain %d%s at %gx\n", a.bag.c_str(),
               participant.domain(), participant.loopback() ? " (loopback only)" : "", a.rate);
  const ros2::PlayReport r = ros2::play_bag(*bag, participant, play);
  for (const std::string& s : r.skipped_types) {
    std::fprintf(stderr, "[bag play] not played (no ROS 2 encoding for its type): %s\n", s.c_str());
  }
  std::fprintf(stderr, "[bag play] %zu messages in %.1f s\n", r.published, r.seconds);
}

}  // namespace

void add_bag_play_command(CLI::App& bag) {
  auto a = std::make_shared<PlayArgs>();
  CLI::App* play = bag.add_subcommand(
      "play", "Publish a bag's messages on a ROS 2 graph (Fast DDS, ROS 2's names, types and QoS)");
  play->add_option("bag", a->bag, "ROS 1 bag file or ROS 2 bag folder")
      ->required()
      ->check(input_path("bag"));
  play->add_option("--rate", a->rate, "Pace: 2 plays twice as fast; <= 0 as fast as possible")
      ->capture_default_str();
  play->add_option("--topics", a->topics, "Only these topics (default: every playable topic)")
      ->delimiter(',');
  play->add_option("--map", a->map,
                   "A map_server YAML published first as nav_msgs/OccupancyGrid (transient local)")
      ->check(input_file("--map"));
  play->add_option("--map-topic", a->map_topic, "Topic of --map")->capture_default_str();
  play->add_option("--wait-for-readers", a->wait,
                   "Seconds to wait until every topic has a subscriber before playing")
      ->capture_default_str();
  play->add_option("--domain", a->domain, "DDS domain (default: ROS_DOMAIN_ID, else 0)");
  play->add_flag("--loopback", a->loopback,
                 "127.0.0.1 only, unicast discovery (also with ROS_LOCALHOST_ONLY=1)");
  play->callback([a] { run_bag_play(*a); });
}

}  // namespace vdtnav::tools
