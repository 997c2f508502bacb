"""``map_server``: publishes a map file on ``/map`` (latched), as nav2's
map_server does."""

from __future__ import annotations

from nav_msgs.msg import OccupancyGrid as GridMsg
from rclpy.exceptions import InvalidTopicNameException
from rclpy.validate_topic_name import validate_topic_name

from ..errors import ParameterError
from ..grid.mapio import load_map
from .base import MAP_QOS, NavlabNode, Param, node_main
from .convert import grid_to_msg


class MapServer(NavlabNode):
    PARAMETERS = (
        Param("yaml_filename", "", "map_server YAML (with its PGM/PNG image) or Moving AI .map file"),
        Param("frame_id", "map", "frame of the published map"),
        Param("topic_name", "map", "topic to publish on"),
    )

    def __init__(self, **kwargs) -> None:
        super().__init__("map_server", **kwargs)
        path = self.params["yaml_filename"]
        if not path:
            raise ParameterError("map_server needs a map: -p yaml_filename:=maze.yaml")
        grid = load_map(path)
        topic = self.params["topic_name"]
        try:
            validate_topic_name(topic if topic.startswith("/") else "/" + topic)
        except InvalidTopicNameException as exc:  # (an internal error until session 18: attack run)
            why = str(exc).splitlines()[0].removeprefix("Invalid topic name: ").rstrip(":")
            raise ParameterError(f"parameter topic_name {topic!r} is not a topic name: {why}") from None
        self.publisher = self.create_publisher(GridMsg, topic, MAP_QOS)
        msg = grid_to_msg(grid, self.params["frame_id"], self.get_clock().now().to_msg())
        self.publisher.publish(msg)
        self.log("info", f"publishing {path}: {grid.width}x{grid.height} cells at {grid.resolution:g} m "
                         f"on /{self.params['topic_name'].lstrip('/')}")


main = node_main(MapServer)

if __name__ == "__main__":
    main()
