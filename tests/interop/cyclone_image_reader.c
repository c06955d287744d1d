/* A ROS 2 node on Eclipse Cyclone DDS reading a camera's streams as `dslam publish` sends them: subscribes to a
 * vehicle's input topics (colour, depth, mask, odometry) with ROS 2's sensor-data QoS (best effort, volatile,
 * keep last 5) and writes one line per sample it decodes:
 *   image TOPIC SEC NANOSEC HEIGHT WIDTH ENCODING STEP DATA_BYTES
 *   odometry SEC NANOSEC X Y Z
 * Usage: dslam_cyclone_image_reader DOMAIN TOPIC_PREFIX FRAMES TIMEOUT_S OUT_FILE
 * Exits 0 once 4 * FRAMES samples were decoded, 1 on timeout, 2 on bad arguments or a DDS error. Large images
 * need a receive buffer that holds a frame's burst of fragments: set it through CYCLONEDDS_URI, as a ROS 2 user
 * of rmw_cyclonedds does (Internal/SocketReceiveBufferSize). */
#include <stdio.h>
#include <stdlib.h>

#include "cyclone_client.h"
#include "ros2_types.h"

int main(int argc, char** argv) {
  if (argc != 6) {
    fprintf(stderr, "usage: dslam_cyclone_image_reader DOMAIN TOPIC_PREFIX FRAMES TIMEOUT_S OUT_FILE\n");
    return 2;
  }
  const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
  const char* prefix = argv[2];
  const unsigned long wanted = 4 * strtoul(argv[3], NULL, 10);
  const double timeout_s = atof(argv[4]);
  FILE* out = fopen(argv[5], "w");
  if (!out) return 2;
  const dds_entity_t participant = ClientParticipant(domain);
  if (participant < 0) return 2;
  dds_qos_t* qos = Ros2Qos(1);
  const char* image_topics[3] = {"camera/color/image_raw", "camera/depth/image_raw", "camera/instance_mask"};
  dds_entity_t readers[4];
  for (int i = 0; i < 4; ++i) {
    readers[i] = ClientEndpoint(participant, prefix, i < 3 ? image_topics[i] : "odom",
                                i < 3 ? &sensor_msgs_msg_dds__Image__desc : &nav_msgs_msg_dds__Odometry__desc, qos, 0);
    if (readers[i] < 0) {
      fprintf(stderr, "cannot create the reader of %s\n", i < 3 ? image_topics[i] : "odom");
      return 2;
    }
  }
  dds_delete_qos(qos);
  unsigned long decoded = 0;
  const dds_time_t end = dds_time() + (dds_time_t)(timeout_s * 1e9);
  while (dds_time() < end && decoded < wanted) {
    for (int i = 0; i < 4; ++i) {
      void* sample = NULL;
      dds_sample_info_t info;
      while (dds_take(readers[i], &sample, &info, 1, 1) > 0) {
        if (info.valid_data && i < 3) {
          const sensor_msgs_msg_dds__Image_* m = sample;
          fprintf(out, "image %s %d %u %u %u %s %u %u\n", image_topics[i], m->header_.stamp_.sec_,
                  m->header_.stamp_.nanosec_, m->height_, m->width_, m->encoding_, m->step_, m->data_._length);
          ++decoded;
        } else if (info.valid_data) {
          const nav_msgs_msg_dds__Odometry_* m = sample;
          fprintf(out, "odometry %d %u %.17g %.17g %.17g\n", m->header_.stamp_.sec_, m->header_.stamp_.nanosec_,
                  m->pose_.pose_.position_.x_, m->pose_.pose_.position_.y_, m->pose_.pose_.position_.z_);
          ++decoded;
        }
        dds_return_loan(readers[i], &sample, 1);
        sample = NULL;
      }
    }
    dds_sleepfor(DDS_MSECS(5));
  }
  fclose(out);
  dds_delete(participant);
  return decoded >= wanted ? 0 : 1;
}
