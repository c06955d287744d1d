/* A ROS 2 camera driver on Eclipse Cyclone DDS (the library under rmw_cyclonedds): publishes prepared frames
 * (colour, depth, instance mask, odometry) on a vehicle's input topics with ROS 2's sensor-data QoS (best
 * effort, volatile, keep last 5), types from ros2_idl/ros2_types.idl as rosidl puts them on the wire.
 * Usage: dslam_cyclone_camera_driver DOMAIN TOPIC_PREFIX FRAMES_FILE RATE_HZ
 *   TOPIC_PREFIX: "rt/" or "rt/<vehicle>/". FRAMES_FILE has one line per frame:
 *     T_NS HEIGHT WIDTH PX PY PZ QX QY QZ QW SX SY SZ SRX SRY SRZ COLOUR_RGB8 DEPTH_32FC1 MASK_16UC1
 *   (the odometry pose, the twist sigmas per second, and three raw row-major image files).
 * It waits up to 30 s for serve's four readers, publishes every frame at RATE_HZ and exits 0 (1 when no reader
 * matched, 2 on bad arguments, an unreadable file or a DDS error). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cyclone_client.h"
#include "ros2_types.h"

static dds_entity_t Writer(dds_entity_t participant, const char* prefix, const char* name,
                           const dds_topic_descriptor_t* type, const dds_qos_t* qos) {
  return ClientEndpoint(participant, prefix, name, type, qos, 1);
}

static int Matched(dds_entity_t writer) {
  dds_publication_matched_status_t status;
  return dds_get_publication_matched_status(writer, &status) == DDS_RETCODE_OK && status.current_count > 0;
}

/* Reads a whole file into `image->data_` and fills the image's other fields; 0 on failure. */
static int LoadImage(const char* path, uint32_t height, uint32_t width, const char* encoding, uint32_t bytes_per_pixel,
                     int64_t t_ns, sensor_msgs_msg_dds__Image_* image) {
  FILE* f = fopen(path, "rb");
  if (!f) return 0;
  const size_t size = (size_t)height * width * bytes_per_pixel;
  image->data_._buffer = dds_alloc(size);
  image->data_._length = image->data_._maximum = (uint32_t)size;
  image->data_._release = true;
  const size_t got = fread(image->data_._buffer, 1, size, f);
  fclose(f);
  if (got != size) return 0;
  image->header_.stamp_.sec_ = (int32_t)(t_ns / 1000000000LL);
  image->header_.stamp_.nanosec_ = (uint32_t)(t_ns % 1000000000LL);
  image->header_.frame_id_ = dds_string_dup("camera");
  image->height_ = height;
  image->width_ = width;
  image->encoding_ = dds_string_dup(encoding);
  image->is_bigendian_ = 0;
  image->step_ = width * bytes_per_pixel;
  return 1;
}

int main(int argc, char** argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: dslam_cyclone_camera_driver DOMAIN TOPIC_PREFIX FRAMES_FILE RATE_HZ\n");
    return 2;
  }
  const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
  const char* prefix = argv[2];
  FILE* frames = fopen(argv[3], "r");
  const double rate_hz = atof(argv[4]);
  if (!frames || !(rate_hz > 0.0)) {
    fprintf(stderr, "cannot read %s, or bad rate %s\n", argv[3], argv[4]);
    return 2;
  }
  const dds_entity_t participant = ClientParticipant(domain);
  if (participant < 0) return 2;
  dds_qos_t* qos = Ros2Qos(1);
  const dds_entity_t colour = Writer(participant, prefix, "camera/color/image_raw", &sensor_msgs_msg_dds__Image__desc, qos);
  const dds_entity_t depth = Writer(participant, prefix, "camera/depth/image_raw", &sensor_msgs_msg_dds__Image__desc, qos);
  const dds_entity_t mask = Writer(participant, prefix, "camera/instance_mask", &sensor_msgs_msg_dds__Image__desc, qos);
  const dds_entity_t odometry = Writer(participant, prefix, "odom", &nav_msgs_msg_dds__Odometry__desc, qos);
  dds_delete_qos(qos);
  if (colour < 0 || depth < 0 || mask < 0 || odometry < 0) {
    fprintf(stderr, "cannot create the writers\n");
    return 2;
  }
  const dds_time_t wait_end = dds_time() + DDS_SECS(30);
  while (!(Matched(colour) && Matched(depth) && Matched(mask) && Matched(odometry)) && dds_time() < wait_end)
    dds_sleepfor(DDS_MSECS(50));
  if (!(Matched(colour) && Matched(depth) && Matched(mask) && Matched(odometry))) {
    fprintf(stderr, "no reader matched within 30 s\n");
    return 1;
  }
  dds_sleepfor(DDS_SECS(1));  /* let serve's readers match the writers too (discovery is not symmetric) */

  long long t_ns;
  unsigned height, width;
  double pose[7], sigma[6];
  char colour_path[4096], depth_path[4096], mask_path[4096];
  int sent = 0;
  const dds_duration_t period = (dds_duration_t)(1e9 / rate_hz);
  dds_time_t next = dds_time();
  while (fscanf(frames, "%lld %u %u %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %4095s %4095s %4095s", &t_ns,
                &height, &width, &pose[0], &pose[1], &pose[2], &pose[3], &pose[4], &pose[5], &pose[6], &sigma[0],
                &sigma[1], &sigma[2], &sigma[3], &sigma[4], &sigma[5], colour_path, depth_path, mask_path) == 19) {
    sensor_msgs_msg_dds__Image_ images[3];
    memset(images, 0, sizeof images);
    if (!LoadImage(colour_path, height, width, "rgb8", 3, t_ns, &images[0]) ||
        !LoadImage(depth_path, height, width, "32FC1", 4, t_ns, &images[1]) ||
        !LoadImage(mask_path, height, width, "16UC1", 2, t_ns, &images[2])) {
      fprintf(stderr, "cannot read the images of frame %lld\n", t_ns);
      return 2;
    }
    nav_msgs_msg_dds__Odometry_ odom;
    memset(&odom, 0, sizeof odom);
    odom.header_.stamp_ = images[0].header_.stamp_;
    odom.header_.frame_id_ = dds_string_dup("odom");
    odom.child_frame_id_ = dds_string_dup("camera");
    odom.pose_.pose_.position_.x_ = pose[0], odom.pose_.pose_.position_.y_ = pose[1];
    odom.pose_.pose_.position_.z_ = pose[2];
    odom.pose_.pose_.orientation_.x_ = pose[3], odom.pose_.pose_.orientation_.y_ = pose[4];
    odom.pose_.pose_.orientation_.z_ = pose[5], odom.pose_.pose_.orientation_.w_ = pose[6];
    for (int i = 0; i < 6; ++i) odom.twist_.covariance_[7 * i] = sigma[i] * sigma[i];
    if (dds_write(colour, &images[0]) < 0 || dds_write(depth, &images[1]) < 0 || dds_write(mask, &images[2]) < 0 ||
        dds_write(odometry, &odom) < 0) {
      fprintf(stderr, "dds_write failed at frame %lld\n", t_ns);
      return 2;
    }
    for (int i = 0; i < 3; ++i) dds_sample_free(&images[i], &sensor_msgs_msg_dds__Image__desc, DDS_FREE_CONTENTS);
    dds_sample_free(&odom, &nav_msgs_msg_dds__Odometry__desc, DDS_FREE_CONTENTS);
    ++sent;
    next += period;
    const dds_time_t now = dds_time();
    if (next > now) dds_sleepfor(next - now);
  }
  fclose(frames);
  dds_sleepfor(DDS_SECS(1));  /* best effort: give the last frame time to leave before the participant goes */
  dds_delete(participant);
  fprintf(stderr, "published %d frames\n", sent);
  return 0;
}
