#!/usr/bin/python3
"""The ROS 2 package ros2/dslam_msgs as ROS 2's own tools see it, without a ROS installation: catkin_pkg reads
its package.xml (format 3, an ament_cmake interface package), and rosidl translates each .msg to IDL and
parses it, the first steps of `colcon build`. Debian's python3-rosidl, python3-empy and python3-catkin-pkg.
Usage: ros2_package_check.py PACKAGE_DIR. Exit 0 when both accept it, 1 with the reason otherwise."""
import pathlib
import sys
import tempfile

from catkin_pkg.package import parse_package
from rosidl_adapter.msg import convert_msg_to_idl
from rosidl_parser.definition import IdlLocator, Message
from rosidl_parser.parser import parse_idl_file


def fail(message):
    print('ros2_package_check: ' + message, file=sys.stderr)
    sys.exit(1)


def main():
    package_dir = pathlib.Path(sys.argv[1]).resolve()
    package = parse_package(str(package_dir / 'package.xml'))  # raises on an invalid manifest
    if package.package_format != 3:
        fail(f'package.xml is format {package.package_format}, not 3')
    if package.get_build_type() != 'ament_cmake':
        fail(f'build type {package.get_build_type()}, not ament_cmake')
    if 'rosidl_interface_packages' not in [g.name for g in package.member_of_groups]:
        fail('not a member of rosidl_interface_packages: colcon would not generate its interfaces')
    tools = [d.name for d in package.buildtool_depends]
    if 'rosidl_default_generators' not in tools:
        fail('no buildtool_depend on rosidl_default_generators')
    depends = {d.name for d in package.build_depends + package.exec_depends}
    msgs = sorted((package_dir / 'msg').glob('*.msg'))
    if not msgs:
        fail(f'no .msg files in {package_dir / "msg"}')
    cmake = (package_dir / 'CMakeLists.txt').read_text()
    with tempfile.TemporaryDirectory() as out:
        for msg in msgs:
            if f'"msg/{msg.name}"' not in cmake:
                fail(f'CMakeLists.txt does not generate msg/{msg.name}')
            idl = convert_msg_to_idl(package_dir, package.name, msg.relative_to(package_dir), pathlib.Path(out) / 'msg')
            try:
                parsed = parse_idl_file(IdlLocator(pathlib.Path(out), idl.relative_to(out)))
            except Exception as error:  # what colcon build would stop on
                fail(f'rosidl cannot parse {msg.name} translated to IDL: {error}')
            for message in parsed.content.get_elements_of_type(Message):
                for member in message.structure.members:
                    namespaced = getattr(member.type, 'namespaces', None)
                    if namespaced is None and hasattr(member.type, 'value_type'):
                        namespaced = getattr(member.type.value_type, 'namespaces', None)
                    if namespaced and namespaced[0] not in depends | {package.name}:
                        fail(f'{msg.name}: field {member.name} uses {namespaced[0]}, not a dependency of the package')
                print(f'{msg.name}: {len(message.structure.members)} fields parsed by rosidl')
    print(f'{package.name} {package.version}: package.xml format 3 and {len(msgs)} messages accepted')


if __name__ == '__main__':
    main()
