#pragma once
// Hosts of a vehicle network on this machine, for tests and benchmarks of what crosses a real network: each
// host is a network namespace with one Ethernet link (a veth pair) to a bridge in a namespace of its own, a
// link-local address (169.254.0.0/16: traffic that can only ever be local) and a default route on that link,
// so that DDS multicast discovery and UDP flow between hosts as between machines on one switch (no shared
// memory, no loopback shortcut). The links can be impaired: random loss of Ethernet frames (nftables in the
// bridge, either way), a bandwidth cap (tc tbf on both ends of a host's link, with its queueing delay), and
// cut (the host's link down). Everything is removed when the object goes; namespaces a killed process left
// behind are removed by the next one. Needs root, iproute2 and nftables: WhyUnavailable() says what is missing.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dslam::test {

class NetworkHosts {
 public:
  // Empty when this process can make the hosts; otherwise why not (for GTEST_SKIP and the benchmark).
  static std::string WhyUnavailable() {
    if (::geteuid() != 0) return "network namespaces need root (this process is not)";
    if (IpTool().empty()) return "iproute2's ip is not installed";
    if (NftTool().empty()) return "nftables' nft is not installed (scripts/deps.txt)";
    const std::string probe = "dslamnet" + std::to_string(::getpid()) + "_probe";
    if (Run(IpTool() + " netns add " + probe) != 0)
      return "this machine does not let this process make network namespaces";
    Run(IpTool() + " netns del " + probe);
    return {};
  }

  // Hosts named `names` (letters and digits), addresses 169.254.1.1, .2, ... in that order. Throws
  // std::runtime_error naming the command that failed.
  explicit NetworkHosts(const std::vector<std::string>& names)
      : prefix_("dslamnet" + std::to_string(::getpid()) + "_") {
    RemoveLeftovers();
    bridge_ = prefix_ + "br";
    Must("netns add " + bridge_);
    Must("-n " + bridge_ + " link add br0 type bridge");
    Must("-n " + bridge_ + " link set br0 up");
    for (size_t i = 0; i < names.size(); ++i) {
      Host h;
      h.name = names[i];
      h.ns = prefix_ + names[i];
      h.port = "port" + std::to_string(i);
      h.address = "169.254.1." + std::to_string(i + 1);
      Must("netns add " + h.ns);
      Must("link add eth0 netns " + h.ns + " type veth peer name " + h.port + " netns " + bridge_);
      Must("-n " + bridge_ + " link set " + h.port + " master br0");
      Must("-n " + bridge_ + " link set " + h.port + " up");
      Must("-n " + h.ns + " link set lo up");
      Must("-n " + h.ns + " link set eth0 up");
      Must("-n " + h.ns + " addr add " + h.address + "/16 dev eth0");
      Must("-n " + h.ns + " route add default dev eth0");  // multicast (discovery) leaves by the link
      hosts_.push_back(h);
    }
  }
  ~NetworkHosts() {
    for (const Host& h : hosts_) Run(IpTool() + " netns del " + h.ns);
    Run(IpTool() + " netns del " + bridge_);
  }
  NetworkHosts(const NetworkHosts&) = delete;
  NetworkHosts& operator=(const NetworkHosts&) = delete;

  // The program to spawn and its first arguments that run a command on `host`: ip netns exec NS ... (ip
  // executes the command in place, so the process's pid is the command's).
  std::string launcher() const { return IpTool(); }
  // launcher()'s arguments that run `program` with `args` on `host`.
  std::vector<std::string> on(const std::string& host, const std::string& program,
                              const std::vector<std::string>& args) const {
    std::vector<std::string> all = {"netns", "exec", find(host).ns, program};
    all.insert(all.end(), args.begin(), args.end());
    return all;
  }
  std::string address(const std::string& host) const { return find(host).address; }

  // Every Ethernet frame crossing the bridge is dropped with this probability (percent, 0 to 100, in steps of
  // 0.01), either way; 0 removes the rule.
  void setLoss(double percent) {
    RunIn(bridge_, NftTool() + " delete table bridge dslam_loss 2>/dev/null");
    if (percent <= 0.0) return;
    const int per_10000 = static_cast<int>(percent * 100.0 + 0.5);
    std::ostringstream rules;
    rules << "table bridge dslam_loss { chain forwarded { type filter hook forward priority 0; policy accept; "
          << "numgen random mod 10000 < " << per_10000 << " drop; }; }";
    if (RunIn(bridge_, NftTool() + " '" + rules.str() + "'") != 0)
      throw std::runtime_error("nft could not add the loss rule: " + rules.str());
  }

  // IP multicast crosses the bridge, or not (as on networks whose switches drop it): DDS' multicast discovery
  // then fails, and hosts must be given each other's addresses (initial peers).
  void setMulticast(bool on) {
    RunIn(bridge_, NftTool() + " delete table bridge dslam_multicast 2>/dev/null");
    if (on) return;
    const std::string rules =
        "table bridge dslam_multicast { chain forwarded { type filter hook forward priority 0; policy accept; "
        "ip daddr 224.0.0.0/4 drop; }; }";
    if (RunIn(bridge_, NftTool() + " '" + rules + "'") != 0)
      throw std::runtime_error("nft could not drop multicast: " + rules);
  }

  // Both directions of `host`'s link carry at most `mbit_per_s`; 0 removes the cap. A token bucket with a
  // 256 KiB burst and up to 200 ms of queue, as a switch port buffers.
  void setBandwidth(const std::string& host, double mbit_per_s) {
    const Host& h = find(host);
    for (const auto& [ns, dev] : {std::pair{h.ns, std::string("eth0")}, std::pair{bridge_, h.port}}) {
      Run("tc -n " + ns + " qdisc del dev " + dev + " root 2>/dev/null");
      if (mbit_per_s > 0.0) {
        std::ostringstream tbf;
        tbf << "tc -n " << ns << " qdisc add dev " << dev << " root tbf rate " << mbit_per_s
            << "mbit burst 256kb latency 200ms";
        if (Run(tbf.str()) != 0) throw std::runtime_error("could not cap the bandwidth: " + tbf.str());
      }
    }
  }

  // The host's link goes down (as a cable pulled) or up again.
  void setLinkUp(const std::string& host, bool up) {
    Must("-n " + bridge_ + " link set " + find(host).port + (up ? " up" : " down"));
  }

 private:
  struct Host {
    std::string name, ns, port, address;
  };

  const Host& find(const std::string& name) const {
    for (const Host& h : hosts_)
      if (h.name == name) return h;
    throw std::invalid_argument("no host '" + name + "' in this network");
  }

  static std::string Which(const std::vector<std::string>& candidates) {
    for (const auto& c : candidates)
      if (::access(c.c_str(), X_OK) == 0) return c;
    return {};
  }
  static std::string IpTool() { return Which({"/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"}); }
  static std::string NftTool() { return Which({"/usr/sbin/nft", "/sbin/nft", "/usr/bin/nft"}); }
  static int Run(const std::string& command) {
    const int status = std::system(("/bin/bash -c \"" + command + "\" >/dev/null 2>&1").c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  static int RunIn(const std::string& ns, const std::string& command) {
    return Run(IpTool() + " netns exec " + ns + " " + command);
  }
  void Must(const std::string& ip_arguments) {
    if (Run(IpTool() + " " + ip_arguments) != 0)
      throw std::runtime_error("could not make the test network: ip " + ip_arguments);
  }

  // Namespaces of processes that no longer run (a test killed before its destructor ran).
  static void RemoveLeftovers() {
    std::unique_ptr<FILE, int (*)(FILE*)> list(::popen((IpTool() + " netns list 2>/dev/null").c_str(), "r"), ::pclose);
    if (!list) return;
    char line[512];
    std::vector<std::string> stale;
    while (std::fgets(line, sizeof(line), list.get())) {
      std::string name = line;
      name = name.substr(0, name.find_first_of(" \n"));
      if (name.rfind("dslamnet", 0) != 0) continue;
      const pid_t pid = static_cast<pid_t>(std::atol(name.c_str() + 8));
      if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(name);
    }
    for (const auto& name : stale) Run(IpTool() + " netns del " + name);
  }

  std::string prefix_, bridge_;
  std::vector<Host> hosts_;
};

}  // namespace dslam::test
