#include "plugin/object_markers.h"

#include <cmath>
#include <cstdio>

#include "geometry/velocity.h"
#include "plugin/image_message.h"

namespace dslam {
namespace {

visualization_msgs::msg::Marker Base(const FrameEstimate& e, const std::string& ns, int id, int type) {
  visualization_msgs::msg::Marker m;
  m.header().stamp(NsToStamp(e.t_ns));
  m.header().frame_id("world");
  m.ns(ns);
  m.id(id);
  m.type(type);
  m.action(0);
  m.pose().orientation().w(1.0);
  return m;
}

void SetColour(bool moving, visualization_msgs::msg::Marker* m) {
  m->color().r(moving ? 0.9f : 0.6f), m->color().g(moving ? 0.1f : 0.6f), m->color().b(moving ? 0.1f : 0.6f);
  m->color().a(moving ? 0.8f : 0.5f);
}

geometry_msgs::msg::Point ToPoint(const Vec3& p) {
  geometry_msgs::msg::Point out;
  out.x(p.x()), out.y(p.y()), out.z(p.z());
  return out;
}

}  // namespace

visualization_msgs::msg::MarkerArray ObjectMarkers(const FrameEstimate& e, double frame_rate_hz) {
  visualization_msgs::msg::MarkerArray array;
  visualization_msgs::msg::Marker clear = Base(e, "dslam", 0, 0);
  clear.action(kMarkerDeleteAll);
  array.markers().push_back(clear);
  for (const ObjectMotionEstimate& o : e.object_motions) {
    const Vec3 centroid = o.centroidWorld();  // as in the object motion message
    const Vec3 velocity_mps = o.velocityMps(frame_rate_hz);
    visualization_msgs::msg::Marker sphere = Base(e, "dslam_objects", o.object_id, kMarkerSphere);
    sphere.pose().position(ToPoint(centroid));
    sphere.scale().x(1.5), sphere.scale().y(1.5), sphere.scale().z(1.5);
    SetColour(o.is_dynamic, &sphere);
    array.markers().push_back(sphere);
    if (o.is_dynamic && velocity_mps.norm() > 0.0) {
      visualization_msgs::msg::Marker arrow = Base(e, "dslam_velocities", o.object_id, kMarkerArrow);
      arrow.points().push_back(ToPoint(centroid));
      arrow.points().push_back(ToPoint(centroid + velocity_mps));
      arrow.scale().x(0.2), arrow.scale().y(0.4), arrow.scale().z(0.5);  // shaft and head diameters, head length
      SetColour(true, &arrow);
      array.markers().push_back(arrow);
    }
    visualization_msgs::msg::Marker text = Base(e, "dslam_speeds", o.object_id, kMarkerText);
    text.pose().position(ToPoint(centroid - Vec3(0.0, 2.0, 0.0)));  // above: y points down in the camera's world
    text.scale().z(0.8);                                             // text height
    char label[64];
    if (o.is_dynamic)
      std::snprintf(label, sizeof label, "%d: %.0f km/h", o.object_id, o.speed_mps * kMpsToKmh);
    else
      std::snprintf(label, sizeof label, "%d: standing", o.object_id);
    text.text(label);
    SetColour(o.is_dynamic, &text);
    text.color().a(1.0f);
    array.markers().push_back(text);
  }
  return array;
}

}  // namespace dslam
