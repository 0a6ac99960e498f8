"""semgraph.ros: ROS tf into a semgraph scene graph, with no ROS library (docs/ros.md).

Bags (MCAP, rosbag2 sqlite3, ROS 1; told apart by content):

    import semgraph.ros as ros
    report = ros.check_bag("run.mcap")            # `semgraph bag check`
    for f in report.findings: print(f.code, f.parent, f.child, f.count)
    X = report.graph.pose(of="base_link", wrt="odom", at=1700000003.5)
    for r in ros.read_bag("run.mcap"): ...        # TransformRecord / JointStateRecord, streaming

Live ROS 2 over Cyclone DDS (when semgraph was built with it): Listener, Broadcaster.
"""

from . import _semgraph
from ._errors import BagError

if not _semgraph._has_ros:
    raise ImportError("semgraph.ros: semgraph was built without the ROS layer "
                      "(SEMGRAPH_BUILD_ROS=OFF, or its libraries were missing: scripts/setup.sh --ros)")

_ros = _semgraph._ros
BagFrame = _ros.BagFrame
BagInfo = _ros.BagInfo
BagRecords = _ros.BagRecords
BagReport = _ros.BagReport
BagTopic = _ros.BagTopic
Finding = _ros.Finding
JointStateRecord = _ros.JointStateRecord
TransformRecord = _ros.TransformRecord
bag_info = _ros.bag_info
check_bag = _ros.check_bag
load_bag = _ros.load_bag
read_bag = _ros.read_bag

__all__ = [
    "BagError",
    "BagFrame",
    "BagInfo",
    "BagRecords",
    "BagReport",
    "BagTopic",
    "Finding",
    "JointStateRecord",
    "TransformRecord",
    "bag_info",
    "check_bag",
    "load_bag",
    "read_bag",
]

if _semgraph._has_ros_dds:
    Broadcaster = _ros.Broadcaster
    Listener = _ros.Listener
    __all__ += ["Broadcaster", "Listener"]
