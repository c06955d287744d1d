/* A ROS 2 node's view of `dslam serve`, through Eclipse Cyclone DDS (the library under rmw_cyclonedds):
 * subscribes to one vehicle's outputs with ROS 2's default subscription QoS (reliable, volatile, keep last
 * 10), types from ros2_idl/ros2_types.idl as rosidl puts them on the wire, and writes every sample it
 * decodes to a file, one line each (numbers with 17 significant digits):
 *   odometry SEC NANOSEC FRAME_ID CHILD_FRAME_ID X Y Z QX QY QZ QW
 *   objects SEC NANOSEC FRAME_ID COUNT, then per object:
 *   object ID IS_DYNAMIC SPEED VX VY VZ CX CY CZ QW COV00 COV35 COV_FINITE
 *   status SEC NANOSEC VEHICLE|- RECEIVED ASSEMBLED PROCESSED INCOMPLETE QUEUE_FULL REJECTED LOST LATENCY_MS
 *   markers SEC NANOSEC COUNT (the first marker's stamp), then per marker:
 *   marker NS ID TYPE ACTION POINTS TEXT (the text last, spaces kept; "-" when empty)
 * Usage: dslam_cyclone_listener DOMAIN TOPIC_PREFIX FRAMES TIMEOUT_S OUT_FILE
 *   TOPIC_PREFIX: "rt/" or "rt/<vehicle>/". Exits 0 once FRAMES camera estimates, FRAMES marker arrays and a
 *   status counting FRAMES processed frames were decoded, 1 on timeout, 2 on bad arguments or a DDS error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cyclone_client.h"
#include "ros2_types.h"

static dds_entity_t Reader(dds_entity_t participant, const char* prefix, const char* name,
                           const dds_topic_descriptor_t* type, const dds_qos_t* qos) {
  char dslam_name[128];
  snprintf(dslam_name, sizeof dslam_name, "dslam/%s", name);
  return ClientEndpoint(participant, prefix, dslam_name, type, qos, 0);
}

static const char* Text(const char* s) { return s && s[0] ? s : "-"; }

int main(int argc, char** argv) {
  if (argc != 6) {
    fprintf(stderr, "usage: dslam_cyclone_listener DOMAIN TOPIC_PREFIX FRAMES TIMEOUT_S OUT_FILE\n");
    return 2;
  }
  const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
  const char* prefix = argv[2];
  const unsigned long frames = strtoul(argv[3], NULL, 10);
  const double timeout_s = atof(argv[4]);
  FILE* out = fopen(argv[5], "w");
  if (!out) {
    fprintf(stderr, "cannot write %s\n", argv[5]);
    return 2;
  }
  const dds_entity_t participant = ClientParticipant(domain);
  if (participant < 0) return 2;
  dds_qos_t* qos = Ros2Qos(0);
  const dds_entity_t odometry = Reader(participant, prefix, "camera_odometry", &nav_msgs_msg_dds__Odometry__desc, qos);
  const dds_entity_t objects =
      Reader(participant, prefix, "object_motions", &dslam_msgs_msg_dds__ObjectMotionArray__desc, qos);
  const dds_entity_t status = Reader(participant, prefix, "status", &dslam_msgs_msg_dds__Status__desc, qos);
  const dds_entity_t markers =
      Reader(participant, prefix, "markers", &visualization_msgs_msg_dds__MarkerArray__desc, qos);
  dds_delete_qos(qos);
  if (odometry < 0 || objects < 0 || status < 0 || markers < 0) {
    fprintf(stderr, "cannot create the readers\n");
    return 2;
  }

  unsigned long odometry_count = 0, processed = 0, marker_arrays = 0;
  const dds_time_t end = dds_time() + (dds_time_t)(timeout_s * 1e9);
  while (dds_time() < end && !(odometry_count >= frames && processed >= frames && marker_arrays >= frames)) {
    void* sample = NULL;
    dds_sample_info_t info;
    while (dds_take(odometry, &sample, &info, 1, 1) > 0) {
      const nav_msgs_msg_dds__Odometry_* m = sample;
      if (info.valid_data) {
        const geometry_msgs_msg_dds__Pose_* p = &m->pose_.pose_;
        fprintf(out, "odometry %d %u %s %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", m->header_.stamp_.sec_,
                m->header_.stamp_.nanosec_, Text(m->header_.frame_id_), Text(m->child_frame_id_), p->position_.x_,
                p->position_.y_, p->position_.z_, p->orientation_.x_, p->orientation_.y_, p->orientation_.z_,
                p->orientation_.w_);
        ++odometry_count;
      }
      dds_return_loan(odometry, &sample, 1);
      sample = NULL;
    }
    while (dds_take(objects, &sample, &info, 1, 1) > 0) {
      const dslam_msgs_msg_dds__ObjectMotionArray_* m = sample;
      if (info.valid_data) {
        fprintf(out, "objects %d %u %s %u\n", m->header_.stamp_.sec_, m->header_.stamp_.nanosec_,
                Text(m->header_.frame_id_), m->objects_._length);
        for (uint32_t i = 0; i < m->objects_._length; ++i) {
          const dslam_msgs_msg_dds__ObjectMotion_* o = &m->objects_._buffer[i];
          int finite = 1;
          for (int j = 0; j < 36; ++j) finite = finite && isfinite(o->covariance_[j]);
          fprintf(out, "object %d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %d %.17g %d\n",
                  o->object_id_, o->is_dynamic_ ? 1 : 0, o->speed_mps_, o->velocity_mps_.x_, o->velocity_mps_.y_,
                  o->velocity_mps_.z_, o->centroid_world_.x_, o->centroid_world_.y_, o->centroid_world_.z_,
                  o->h_world_.orientation_.w_, o->covariance_[0], o->covariance_[35], finite, o->centroid_camera_.z_,
                  o->box_width_);
        }
      }
      dds_return_loan(objects, &sample, 1);
      sample = NULL;
    }
    while (dds_take(status, &sample, &info, 1, 1) > 0) {
      const dslam_msgs_msg_dds__Status_* m = sample;
      if (info.valid_data) {
        fprintf(out, "status %d %u %s %llu %llu %llu %llu %llu %llu %llu %.17g\n", m->header_.stamp_.sec_,
                m->header_.stamp_.nanosec_, Text(m->vehicle_), (unsigned long long)m->frames_received_,
                (unsigned long long)m->frames_assembled_, (unsigned long long)m->frames_processed_,
                (unsigned long long)m->dropped_incomplete_, (unsigned long long)m->dropped_queue_full_,
                (unsigned long long)m->rejected_invalid_, (unsigned long long)m->samples_lost_, m->last_latency_ms_);
        if (m->frames_processed_ > processed) processed = (unsigned long)m->frames_processed_;
      }
      dds_return_loan(status, &sample, 1);
      sample = NULL;
    }
    while (dds_take(markers, &sample, &info, 1, 1) > 0) {
      const visualization_msgs_msg_dds__MarkerArray_* m = sample;
      if (info.valid_data) {
        const uint32_t n = m->markers_._length;
        fprintf(out, "markers %d %u %u\n", n ? m->markers_._buffer[0].header_.stamp_.sec_ : 0,
                n ? m->markers_._buffer[0].header_.stamp_.nanosec_ : 0u, n);
        ++marker_arrays;
        for (uint32_t i = 0; i < n; ++i) {
          const visualization_msgs_msg_dds__Marker_* k = &m->markers_._buffer[i];
          fprintf(out, "marker %s %d %d %d %u %s\n", Text(k->ns_), k->id_, k->type_, k->action_, k->points_._length,
                  Text(k->text_));
        }
      }
      dds_return_loan(markers, &sample, 1);
      sample = NULL;
    }
    fflush(out);
    dds_sleepfor(DDS_MSECS(10));
  }
  fclose(out);
  dds_delete(participant);
  return odometry_count >= frames && processed >= frames && marker_arrays >= frames ? 0 : 1;
}
