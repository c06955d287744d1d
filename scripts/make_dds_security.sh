#!/usr/bin/env bash
# Creates a test DDS Security setup (DDS Security 1.1 built-in plugins of Fast DDS): a certificate
# authority, one identity (certificate + key) and one signed permissions document per participant
# name, a signed governance document (authentication required, access control on every topic,
# discovery, liveliness and data encrypted with AES-GCM), and per participant a Fast DDS profiles file:
# config/dds_profiles.xml with the security properties added to its participant profile.
# Usage: scripts/make_dds_security.sh OUT_DIR NAME [NAME...]     e.g. ... results/dds_security serve publisher
# Then: dslam serve --profiles OUT_DIR/serve_profiles.xml ...; dslam publish --profiles OUT_DIR/publisher_profiles.xml ...
# For tests and demonstrations only: the CA key sits beside the certificates, unprotected.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ "$#" -lt 2 ]; then
  echo "usage: $0 OUT_DIR NAME [NAME...]" >&2
  exit 2
fi
out="$1"
shift
mkdir -p "$out"
out="$(cd "$out" && pwd)"
cd "$out"

ecparam=(-newkey ec -pkeyopt ec_paramgen_curve:prime256v1)
if [ ! -f ca_key.pem ]; then
  openssl req -x509 -nodes -days 3650 "${ecparam[@]}" -keyout ca_key.pem -out ca_cert.pem \
    -subj "/C=ES/O=dslam test/CN=dslam test CA" 2>/dev/null
fi

now="$(date -u +%Y-%m-%dT%H:%M:%S)"
cat > governance.xml <<GOV
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
GOV
openssl smime -sign -in governance.xml -text -out governance.smime -signer ca_cert.pem -inkey ca_key.pem

for name in "$@"; do
  subject="/C=ES/O=dslam test/CN=$name"
  openssl req -nodes "${ecparam[@]}" -keyout "${name}_key.pem" -out "${name}.csr" -subj "$subject" 2>/dev/null
  openssl x509 -req -days 3650 -in "${name}.csr" -CA ca_cert.pem -CAkey ca_key.pem -CAcreateserial \
    -out "${name}_cert.pem" 2>/dev/null
  rm -f "${name}.csr"
  # The subject as the certificate prints it (RFC 2253 order is what Fast DDS compares).
  dn="$(openssl x509 -in "${name}_cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')"
  cat > "${name}_permissions.xml" <<PERM
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <permissions>
    <grant name="${name}">
      <subject_name>${dn}</subject_name>
      <validity><not_before>2020-01-01T00:00:00</not_before><not_after>2035-01-01T00:00:00</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>232</max></id_range></domains>
        <publish><topics><topic>*</topic></topics></publish>
        <subscribe><topics><topic>*</topic></topics></subscribe>
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
PERM
  openssl smime -sign -in "${name}_permissions.xml" -text -out "${name}_permissions.smime" -signer ca_cert.pem \
    -inkey ca_key.pem
  properties="        <propertiesPolicy>
          <properties>
            <property><name>dds.sec.auth.plugin</name><value>builtin.PKI-DH</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_ca</name><value>file://${out}/ca_cert.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.identity_certificate</name><value>file://${out}/${name}_cert.pem</value></property>
            <property><name>dds.sec.auth.builtin.PKI-DH.private_key</name><value>file://${out}/${name}_key.pem</value></property>
            <property><name>dds.sec.access.plugin</name><value>builtin.Access-Permissions</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.permissions_ca</name><value>file://${out}/ca_cert.pem</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.governance</name><value>file://${out}/governance.smime</value></property>
            <property><name>dds.sec.access.builtin.Access-Permissions.permissions</name><value>file://${out}/${name}_permissions.smime</value></property>
            <property><name>dds.sec.crypto.plugin</name><value>builtin.AES-GCM-GMAC</value></property>
          </properties>
        </propertiesPolicy>"
  # Insert the properties into the participant profile's <rtps> element of the shipped profiles.
  awk -v props="$properties" '{ print } /<name>dslam<\/name>/ { print props }' \
    "$root/config/dds_profiles.xml" > "${name}_profiles.xml"
done
echo "DDS security files in $out: ca_cert.pem, governance.smime, and per participant NAME_cert.pem, NAME_key.pem,"
echo "NAME_permissions.smime, NAME_profiles.xml (use with --profiles)"
