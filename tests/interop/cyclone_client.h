/* What the Cyclone DDS clients of the interop tests share: a participant, ROS 2's two QoS profiles, topics
 * named with the vehicle's prefix. Header-only: each client is one C file. */
#ifndef DSLAM_TESTS_INTEROP_CYCLONE_CLIENT_H
#define DSLAM_TESTS_INTEROP_CYCLONE_CLIENT_H

#include <stdio.h>

#include "dds/dds.h"

/* A participant on `domain`; prints the error and returns a negative value when it cannot be created. */
static inline dds_entity_t ClientParticipant(dds_domainid_t domain) {
  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) fprintf(stderr, "dds_create_participant: %s\n", dds_strretcode(-participant));
  return participant;
}

/* rclcpp's default QoS (reliable, volatile, keep last 10), or with `sensor_data` rclcpp::SensorDataQoS()
 * (best effort, volatile, keep last 5). The caller deletes it. */
static inline dds_qos_t* Ros2Qos(int sensor_data) {
  dds_qos_t* qos = dds_create_qos();
  if (sensor_data)
    dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  else
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, sensor_data ? 5 : 10);
  return qos;
}

/* A reader (`writer` 0) or writer of topic PREFIX + NAME; negative on failure. */
static inline dds_entity_t ClientEndpoint(dds_entity_t participant, const char* prefix, const char* name,
                                          const dds_topic_descriptor_t* type, const dds_qos_t* qos, int writer) {
  char topic_name[256];
  snprintf(topic_name, sizeof topic_name, "%s%s", prefix, name);
  const dds_entity_t topic = dds_create_topic(participant, type, topic_name, NULL, NULL);
  if (topic < 0) return topic;
  return writer ? dds_create_writer(participant, topic, qos, NULL) : dds_create_reader(participant, topic, qos, NULL);
}

#endif
