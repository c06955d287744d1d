// The vehicle network, measured: a camera host (dslam publish), a compute host (dslam serve) and a display host
// (dslam listen) in network namespaces on one bridge (tests/support/network_hosts.h), Fast DDS over UDP between
// them, every link capped at 100 Mbit/s, 10 Hz, KITTI-size frames (1242x375 colour, depth, mask, odometry), with
// 0, 1 and 5 % of Ethernet frames dropped at random. For each transport choice (profile file, image
// compression) it prints the frames serve estimated, the frames the display host received, the latency from
// capture (publish --stamp-now) to the estimate at the display host, and serve's own stages. The camera host
// encodes its frames before sending the first (publish --preload): on this one machine its per-frame encoding
// would otherwise take serve's cores, which a separate camera computer does not. Needs root, iproute2 and
// nftables.
// Usage: bench_vehicle_network [DATASET_DIR] [frames=60] [PROFILES.xml | --fleet]
//   (without a dataset, or with "", it renders the city; needs Xvfb. With a profile file, only that profile is
//   measured, with PNG and JPEG images: to try a QoS of one's own. --fleet: instead, 1, 2 and 3 vehicles, each on
//   its own camera host, served by one serve host: the capacity of one host, with the camera hosts encoding each
//   frame as they send it and with every frame encoded beforehand.)
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/render_scene_command.h"
#include "data/image_dataset.h"
#include "plugin/compressed_image.h"
#include "plugin/image_message.h"
#include "tests/support/child_process.h"
#include "tests/support/network_hosts.h"

namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

struct Transport {
  std::string name, profiles, compress;
};

// Mean bytes a frame's images take on the wire with `compress` (colour, depth, mask), over the first frames.
double BytesPerFrame(const dslam::ImageDataset& data, const std::string& compress, int frames) {
  double total = 0.0;
  const int n = std::min(frames, data.size());
  for (int i = 0; i < n; ++i) {
    const dslam::ImageFrame f = data.read(i);
    const std::pair<const cv::Mat*, dslam::ImageRole> images[] = {{&f.image, dslam::ImageRole::kColour},
                                                                  {&f.depth_m, dslam::ImageRole::kDepth},
                                                                  {&f.instance_ids, dslam::ImageRole::kMask}};
    for (const auto& [image, role] : images) {
      if (image->empty()) continue;
      if (compress == "none") {
        const cv::Mat sent = role == dslam::ImageRole::kMask ? dslam::MaskForTransport(*image) : *image;
        total += static_cast<double>(dslam::EncodeImage(sent, role, f.t_ns, "camera").data().size());
      } else {
        total += static_cast<double>(
            dslam::EncodeCompressedImage(*image, role, *dslam::ParseImageCompression(compress), f.t_ns, "camera")
                .data()
                .size());
      }
    }
  }
  return n > 0 ? total / n : 0.0;
}

void RunOne(const std::string& dataset, int frames, const Transport& t, double loss_percent, const std::string& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  dslam::test::NetworkHosts net({"camera", "compute", "display"});
  for (const char* host : {"camera", "compute", "display"}) net.setBandwidth(host, 100.0);
  net.setLoss(loss_percent);
  dslam::test::Process serve(net.launcher(),
                             net.on("compute", DSLAM_BINARY,
                                    {"serve", "--calib", dataset + "/calib.txt", "--profiles", t.profiles, "--out",
                                     dir + "/serve", "--status-every", "0"}),
                             dir + "/serve.log");
  dslam::test::Process listen(net.launcher(),
                              net.on("display", DSLAM_BINARY,
                                     {"listen", "--profiles", t.profiles, "--out", dir + "/listen", "--idle-stop", "5",
                                      "--max-run", "300", "--status-every", "0"}),
                              dir + "/listen.log");
  if (!dslam::test::WaitForLogLine(dir + "/listen.log", "1 writer of estimates matched", 60s)) {
    std::printf("  %-22s loss %3.0f %%: the display host never matched serve's writer\n", t.name.c_str(), loss_percent);
    return;
  }
  dslam::test::Process publish(
      net.launcher(),
      net.on("camera", DSLAM_BINARY,
             {"publish", "--dataset", dataset, "--profiles", t.profiles, "--rate", "10", "--compress", t.compress,
              "--stamp-now", "--preload", "--wait", "60", "--frames", std::to_string(frames)}),
      dir + "/publish.log");
  publish.wait(300s);
  // serve stops first (it estimates what it has assembled, and publishes it), then the display host, which ends
  // 5 s after the last estimate: everything serve published had the time to arrive.
  std::this_thread::sleep_for(3s);
  serve.signal(SIGTERM);
  serve.wait(120s);
  if (listen.wait(10s) == -1) listen.signal(SIGTERM), listen.wait(30s);  // it received nothing to be idle after
  const nlohmann::json run = dslam::test::ReadJsonObject(dir + "/serve/default/metrics.json")["run"];
  const nlohmann::json seen = dslam::test::ReadJsonObject(dir + "/listen/listen.json");
  const auto stage = [&](const char* name) {
    if (!run.is_object() || !run.contains("latency_ms") || !run["latency_ms"].contains(name)) return std::string("-");
    char s[32];
    std::snprintf(s, sizeof(s), "%.0f/%.0f", run["latency_ms"][name].value("median_ms", 0.0),
                  run["latency_ms"][name].value("p99_ms", 0.0));
    return std::string(s);
  };
  std::string capture = "-";
  if (seen.contains("capture_to_receipt_ms")) {
    char s[32];
    std::snprintf(s, sizeof(s), "%.0f/%.0f", seen["capture_to_receipt_ms"].value("median_ms", 0.0),
                  seen["capture_to_receipt_ms"].value("p99_ms", 0.0));
    capture = s;
  }
  const int estimated = run.is_object() ? run.value("frames", 0) : 0;
  std::printf(
      "  %-22s loss %3.0f %%: estimated %3d/%d, at the display %3d, capture->display %9s ms, lost %3d, "
      "incomplete %3d, backlog %3d | input %s, decode %s, front-end %s, back-end %s\n",
      t.name.c_str(), loss_percent, estimated, frames, seen.value("frames", 0), capture.c_str(),
      run.is_object() ? run.value("samples_lost", 0) : 0, run.is_object() ? run.value("dropped_incomplete", 0) : 0,
      run.is_object() ? run.value("dropped_queue_full", 0) : 0, stage("input").c_str(), stage("decode").c_str(),
      stage("frontend").c_str(), stage("backend").c_str());
  std::fflush(stdout);
}

// N vehicles, each its own camera host, served by one compute host (serve --vehicle v0 ... in its default
// newest-frame-wins mode) at 10 Hz each, with a subscriber per vehicle on the display host: the frames estimated
// per vehicle tell whether one host keeps up with N. `preload`: the camera hosts encode every frame before
// sending the first (publish --preload), so that on this one machine their per-frame work does not take the
// serve host's processor, as separate camera computers would not.
void RunFleet(const std::string& dataset, int frames, int vehicles, const std::string& profiles, bool preload,
              const std::string& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<std::string> names = {"compute", "display"};
  for (int v = 0; v < vehicles; ++v) names.push_back("camera" + std::to_string(v));
  dslam::test::NetworkHosts net(names);
  for (const auto& host : names) net.setBandwidth(host, 100.0);
  std::vector<std::string> serve_args = {"serve", "--calib",      dataset + "/calib.txt", "--profiles", profiles,
                                         "--out", dir + "/serve", "--status-every",       "0"};
  for (int v = 0; v < vehicles; ++v) serve_args.insert(serve_args.end(), {"--vehicle", "v" + std::to_string(v)});
  dslam::test::Process serve(net.launcher(), net.on("compute", DSLAM_BINARY, serve_args), dir + "/serve.log");
  std::vector<std::unique_ptr<dslam::test::Process>> listens, publishers;
  for (int v = 0; v < vehicles; ++v) {
    const std::string id = std::to_string(v);
    listens.push_back(std::make_unique<dslam::test::Process>(
        net.launcher(),
        net.on("display", DSLAM_BINARY,
               {"listen", "--vehicle", "v" + id, "--profiles", profiles, "--out", dir + "/listen" + id, "--idle-stop",
                "5", "--max-run", "300", "--status-every", "0"}),
        dir + "/listen" + id + ".log"));
  }
  for (int v = 0; v < vehicles; ++v)
    if (!dslam::test::WaitForLogLine(dir + "/listen" + std::to_string(v) + ".log", "1 writer of estimates matched",
                                     60s)) {
      std::printf("  %d vehicles: the display host never matched vehicle %d's writer\n", vehicles, v);
      return;
    }
  for (int v = 0; v < vehicles; ++v) {
    const std::string id = std::to_string(v);
    std::vector<std::string> publish = {"publish", "--vehicle", "v" + id, "--dataset", dataset, "--profiles",
                                        profiles, "--rate", "10", "--compress", "jpeg", "--stamp-now", "--wait", "60",
                                        "--frames", std::to_string(frames)};
    if (preload) publish.push_back("--preload");
    publishers.push_back(std::make_unique<dslam::test::Process>(
        net.launcher(), net.on("camera" + id, DSLAM_BINARY, publish), dir + "/publish" + id + ".log"));
  }
  for (auto& p : publishers) p->wait(300s);
  std::this_thread::sleep_for(3s);
  serve.signal(SIGTERM);
  serve.wait(120s);
  int all = 0, worst = frames;
  double worst_p99 = 0.0;
  for (int v = 0; v < vehicles; ++v) {
    auto& listen = listens[static_cast<size_t>(v)];
    if (listen->wait(10s) == -1) listen->signal(SIGTERM), listen->wait(30s);
    const nlohmann::json run =
        dslam::test::ReadJsonObject(dir + "/serve/v" + std::to_string(v) + "/metrics.json")["run"];
    const nlohmann::json seen = dslam::test::ReadJsonObject(dir + "/listen" + std::to_string(v) + "/listen.json");
    const int estimated = run.is_object() ? run.value("frames", 0) : 0;
    all += estimated;
    worst = std::min(worst, estimated);
    if (seen.contains("capture_to_receipt_ms"))
      worst_p99 = std::max(worst_p99, seen["capture_to_receipt_ms"].value("p99_ms", 0.0));
  }
  std::printf(
      "  %d vehicle%s at 10 Hz on one serve host, camera hosts %s: %d of %d frames estimated (the worst vehicle %d "
      "of %d), capture->display p99 %.0f ms (the worst vehicle)\n",
      vehicles, vehicles == 1 ? "" : "s", preload ? "preloaded" : "encoding each frame", all, vehicles * frames, worst,
      frames, worst_p99);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (const std::string why = dslam::test::NetworkHosts::WhyUnavailable(); !why.empty()) {
    std::fprintf(stderr, "bench_vehicle_network: %s\n", why.c_str());
    return 1;
  }
  std::string dataset = argc > 1 ? argv[1] : "";  // "" renders
  const int frames = argc > 2 ? std::atoi(argv[2]) : 60;
  const std::string work = (fs::temp_directory_path() / ("dslam_bench_network_" + std::to_string(::getpid()))).string();
  if (dataset.empty()) {
    dataset = work + "/city";
    dslam::RenderSceneOptions render;
    render.scenario = "city", render.frames = frames, render.out_dir = dataset, render.quiet = true;
    std::ostringstream out, err;
    if (dslam::RunRenderSceneCommand(render, out, err) != 0) {
      std::fprintf(stderr, "bench_vehicle_network: rendering the city failed: %s\n", err.str().c_str());
      return 1;
    }
  }
  const std::string config = DSLAM_SOURCE_DIR "/config/";
  std::vector<Transport> transports = {{"default, raw", config + "dds_profiles.xml", "none"},
                                       {"default, png", config + "dds_profiles.xml", "png"},
                                       {"vehicle network, png", config + "dds_profiles_vehicle_network.xml", "png"},
                                       {"vehicle network, jpeg", config + "dds_profiles_vehicle_network.xml", "jpeg"}};
  const bool fleet = argc > 3 && std::string(argv[3]) == "--fleet";
  if (argc > 3 && !fleet) transports = {{"given, png", argv[3], "png"}, {"given, jpeg", argv[3], "jpeg"}};
  const dslam::ImageDataset data(dataset, dslam::ImageDatasetOptions{});
  std::printf("vehicle network: 3 hosts, links of 100 Mbit/s, %d frames at 10 Hz of %s (%dx%d)\n", frames,
              dataset.c_str(), data.read(0).image.cols, data.read(0).image.rows);
  for (const char* compress : {"none", "png", "jpeg"}) {
    const double bytes = BytesPerFrame(data, compress, 10);
    std::printf("  images on the wire, %-4s: %.2f MB a frame (%.0f Mbit/s at 10 Hz)\n", compress, bytes / 1e6,
                bytes * 8 * 10 / 1e6);
  }
  int index = 0;
  if (fleet) {
    std::printf("fleet: vehicles each on its own camera host, one serve host, vehicle-network profile, JPEG\n");
    for (bool preload : {false, true})
      for (int vehicles : {1, 2, 3})
        RunFleet(dataset, frames, vehicles, config + "dds_profiles_vehicle_network.xml", preload,
                 work + "/fleet" + std::to_string(vehicles) + (preload ? "_preloaded" : ""));
    transports.clear();
  }
  for (const Transport& t : transports)
    for (double loss : {0.0, 1.0, 5.0}) {
      if (t.name.rfind("default", 0) == 0 && loss > 1.0) continue;  // nothing left to show
      RunOne(dataset, frames, t, loss, work + "/run" + std::to_string(index++));
    }
  if (std::getenv("DSLAM_KEEP_TEST_FILES")) {
    std::printf("logs and results kept in %s\n", work.c_str());
  } else {
    fs::remove_all(work);
  }
  return 0;
}
