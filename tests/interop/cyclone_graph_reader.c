/* What `ros2 node list` and `ros2 node info` see of `dslam serve`, through Eclipse Cyclone DDS: reads the ROS 2
 * graph topic ros_discovery_info (rmw_dds_common/msg/ParticipantEntitiesInfo, reliable, transient local, as
 * every rmw reads it) in the GID layout of one distribution, and the DDS discovery of every endpoint
 * (DCPSPublication, DCPSSubscription), which the graph's GIDs must name. Writes to a file:
 *   participant GID_HEX NODES
 *   node NAMESPACE NAME READERS WRITERS, then per GID: reader GID_HEX / writer GID_HEX
 *   publication GUID_HEX PARTICIPANT_GUID_HEX TOPIC TYPE (subscription likewise), for every endpoint discovered
 * GID_HEX is the whole array (32 or 48 hex digits). Usage:
 *   dslam_cyclone_graph_reader DOMAIN GID_WIDTH NODES TIMEOUT_S OUT_FILE
 * GID_WIDTH: 16 (Iron and later) or 24 (Humble). Exits 0 once a graph sample with NODES nodes was decoded and
 * every endpoint GID it lists was discovered, 1 on timeout, 2 on bad arguments or a DDS error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cyclone_client.h"
#include "ros2_types.h"

#define MAX_ENDPOINTS 256

static void Hex(const uint8_t* data, int n, char* out) {
  for (int i = 0; i < n; ++i) sprintf(out + 2 * i, "%02x", data[i]);
  out[2 * n] = '\0';
}

/* The endpoints discovered so far (their GUIDs), to check that every GID of the graph names one. */
static uint8_t discovered[MAX_ENDPOINTS][16];
static int discovered_count = 0;

static int Discovered(const uint8_t* gid) {
  for (int i = 0; i < discovered_count; ++i)
    if (memcmp(discovered[i], gid, 16) == 0) return 1;
  return 0;
}

static void TakeEndpoints(dds_entity_t reader, const char* kind, FILE* out) {
  void* samples[1] = {NULL};
  dds_sample_info_t info;
  while (dds_take(reader, samples, &info, 1, 1) > 0) {
    const dds_builtintopic_endpoint_t* e = samples[0];
    if (info.valid_data && discovered_count < MAX_ENDPOINTS && !Discovered(e->key.v)) {
      char guid[33], participant[33];
      Hex(e->key.v, 16, guid);
      Hex(e->participant_key.v, 16, participant);
      fprintf(out, "%s %s %s %s %s\n", kind, guid, participant, e->topic_name, e->type_name);
      memcpy(discovered[discovered_count++], e->key.v, 16);
    }
    dds_return_loan(reader, samples, 1);
    samples[0] = NULL;
  }
}

/* The two layouts differ only in the GID's width: one walk over either. Writes to `f` unless NULL; sets
 * `all_discovered` when every GID listed names a discovered endpoint. */
#define WALK_GRAPH(M, WIDTH)                                                                           \
  do {                                                                                                 \
    const M##ParticipantEntitiesInfo_* g = sample;                                                     \
    char hex[2 * (WIDTH) + 1];                                                                         \
    Hex(g->gid_.data_, WIDTH, hex);                                                                    \
    if (f) fprintf(f, "participant %s %u\n", hex, g->node_entities_info_seq_._length);               \
    *nodes = g->node_entities_info_seq_._length;                                                       \
    for (uint32_t i = 0; i < g->node_entities_info_seq_._length; ++i) {                                \
      const M##NodeEntitiesInfo_* n = &g->node_entities_info_seq_._buffer[i];                          \
      if (f)                                                                                           \
        fprintf(f, "node %s %s %u %u\n", n->node_namespace_, n->node_name_, n->reader_gid_seq_._length, \
                n->writer_gid_seq_._length);                                                           \
      for (uint32_t j = 0; j < n->reader_gid_seq_._length; ++j) {                                      \
        Hex(n->reader_gid_seq_._buffer[j].data_, WIDTH, hex);                                          \
        if (f) fprintf(f, "reader %s\n", hex);                                                         \
        all_discovered = all_discovered && Discovered(n->reader_gid_seq_._buffer[j].data_);            \
      }                                                                                                \
      for (uint32_t j = 0; j < n->writer_gid_seq_._length; ++j) {                                      \
        Hex(n->writer_gid_seq_._buffer[j].data_, WIDTH, hex);                                          \
        if (f) fprintf(f, "writer %s\n", hex);                                                         \
        all_discovered = all_discovered && Discovered(n->writer_gid_seq_._buffer[j].data_);            \
      }                                                                                                \
    }                                                                                                  \
  } while (0)

/* The last graph sample (read, not taken: it is checked again as more endpoints are discovered): -1 when
 * none yet, else whether every GID it lists was discovered; its node count in `nodes`. */
static int Graph(dds_entity_t reader, int width, FILE* f, unsigned* nodes) {
  void* sample = NULL;
  dds_sample_info_t info;
  int result = -1;
  if (dds_read(reader, &sample, &info, 1, 1) > 0) {
    if (info.valid_data) {
      int all_discovered = 1;
      if (width == 24)
        WALK_GRAPH(rmw_dds_common_humble_msg_dds__, 24);
      else
        WALK_GRAPH(rmw_dds_common_msg_dds__, 16);
      result = all_discovered;
    }
    dds_return_loan(reader, &sample, 1);
  }
  return result;
}

int main(int argc, char** argv) {
  if (argc != 6 || (atoi(argv[2]) != 16 && atoi(argv[2]) != 24)) {
    fprintf(stderr, "usage: dslam_cyclone_graph_reader DOMAIN GID_WIDTH(16|24) NODES TIMEOUT_S OUT_FILE\n");
    return 2;
  }
  const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
  const int width = atoi(argv[2]);
  const unsigned expected_nodes = (unsigned)strtoul(argv[3], NULL, 10);
  const double timeout_s = atof(argv[4]);
  const dds_entity_t participant = ClientParticipant(domain);
  if (participant < 0) return 2;
  /* Humble's layout under the DDS type name both distributions use. */
  dds_topic_descriptor_t humble = rmw_dds_common_humble_msg_dds__ParticipantEntitiesInfo__desc;
  humble.m_typename = rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc.m_typename;
  const dds_topic_descriptor_t* type = width == 24 ? &humble : &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc;
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  const dds_entity_t graph = ClientEndpoint(participant, "", "ros_discovery_info", type, qos, 0);
  dds_delete_qos(qos);
  const dds_entity_t publications = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, NULL, NULL);
  const dds_entity_t subscriptions = dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION, NULL, NULL);
  if (graph < 0 || publications < 0 || subscriptions < 0) {
    fprintf(stderr, "cannot create the readers\n");
    return 2;
  }
  FILE* out = fopen(argv[5], "w");
  if (!out) {
    fprintf(stderr, "cannot write %s\n", argv[5]);
    return 2;
  }

  unsigned nodes = 0;
  int state = -1;
  const dds_time_t end = dds_time() + (dds_time_t)(timeout_s * 1e9);
  while (dds_time() < end && !(state == 1 && nodes == expected_nodes)) {
    dds_sleepfor(DDS_MSECS(50));
    TakeEndpoints(publications, "publication", out);
    TakeEndpoints(subscriptions, "subscription", out);
    state = Graph(graph, width, NULL, &nodes);
  }
  Graph(graph, width, out, &nodes);
  fclose(out);
  dds_delete(participant);
  return state == 1 && nodes == expected_nodes ? 0 : 1;
}
