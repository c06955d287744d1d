#include "plugin/transport_profiles.h"

#include <stdexcept>

#include <fastrtps/xmlparser/XMLProfileManager.h>

namespace dslam {

std::string WithoutSharedMemoryTransport(const std::string& profiles_xml) {
  std::string xml = profiles_xml;
  const std::string shm = "<transport_id>dslam_shm</transport_id>";
  const size_t user = xml.find("<userTransports>");
  const size_t at = user == std::string::npos ? std::string::npos : xml.find(shm, user);
  if (at == std::string::npos)
    throw std::invalid_argument("the profiles list no " + shm + " in <userTransports>");
  xml.erase(at, shm.size());
  return xml;
}

void DisableIntraprocessDelivery() {
  eprosima::fastrtps::LibrarySettingsAttributes settings;
  settings.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
  eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(settings);
}

}  // namespace dslam
