"""A Ctrl-C while ``navlab ros demo`` builds its in-process nodes (run by test_demo_signals.py inside a private
network namespace): the map_server node's construction ends with a SIGINT to this process, as a user's Ctrl-C
during a first start (the pathplanner compiling its kernels) would come. Prints one JSON object: the nodes
built and the mission's summary (what the demo says goes to this process's stderr)."""

import json
import os
import signal

from navlab.ros import demo

built = []
real_node_class = demo.node_class


def node_class(name):
    real = real_node_class(name)

    def build(**kwargs):
        node = real(**kwargs)
        built.append(name)
        if name == "map_server":
            os.kill(os.getpid(), signal.SIGINT)  # the handler runs here, while the node is still being built
        return node
    return build


demo.node_class = node_class
summary = demo.run_demo(maze_size=3, timeout=60)
demo.node_class = real_node_class
print(json.dumps({"built": built, "reason": summary.get("reason")}, default=str))
