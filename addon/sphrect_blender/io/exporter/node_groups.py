"""Node groups, followed as Cycles compiles them (inlined): a link from a Group node's output continues inside
the group at its Group Output, and a link from a Group Input continues at the Group node's input outside (its
own value when nothing is linked there).  Nested groups work the same way.

The exporter reads node trees through sockets (`is_linked`, `links[0].from_node`, `default_value`) and nodes
(`inputs[...]`, properties).  Nodes and sockets inside a group are handed to it wrapped (GroupNode,
GroupSocket), carrying the chain of Group nodes they sit in, so that the same reads see through the group.
Nodes outside any group stay Blender's own: materials without groups read exactly as before."""

_GROUP, _GROUP_INPUT, _GROUP_OUTPUT, _REROUTE = "ShaderNodeGroup", "NodeGroupInput", "NodeGroupOutput", "NodeReroute"
MAX_GROUP_DEPTH = 16  # deeper (or recursive) groups: the link is treated as absent


def _unwrap(socket):
    return socket.socket if isinstance(socket, GroupSocket) else socket


def _context(socket):
    return socket.groups if isinstance(socket, GroupSocket) else ()


def _group_output_input(group_node, output_socket):
    """The Group Output input inside `group_node`'s tree that its output `output_socket` shows."""
    tree = group_node.node_tree
    if tree is None:
        return None
    index = list(group_node.outputs).index(output_socket)
    outputs = [n for n in tree.nodes if n.bl_idname == _GROUP_OUTPUT]
    active = [n for n in outputs if getattr(n, "is_active_output", False)] or outputs
    return active[0].inputs[index] if active and index < len(active[0].inputs) else None


def _through(link, groups):
    """Where a link from a reroute or a Group Input continues: (the input socket upstream, its groups), or None
    when it continues nowhere (a Group Input outside any group); False for a link from any other node."""
    node = link.from_node
    if node.bl_idname == _REROUTE:
        return node.inputs[0], groups
    if node.bl_idname != _GROUP_INPUT:
        return False
    if not groups:
        return None
    outer, index = groups[-1], list(node.outputs).index(link.from_socket)
    return (outer.inputs[index], groups[:-1]) if index < len(outer.inputs) else None


def resolve(socket):
    """(node, output socket, groups) feeding input `socket` through reroutes and groups, or None; the node is the
    real one, `groups` the chain of Group nodes it sits in."""
    real, groups = _unwrap(socket), _context(socket)
    for _ in range(64 * MAX_GROUP_DEPTH):
        if real is None or not real.is_linked:
            return None
        link = real.links[0]
        upstream = _through(link, groups)
        if upstream is None:
            return None
        if upstream is not False:
            real, groups = upstream
        elif link.from_node.bl_idname == _GROUP:
            if len(groups) >= MAX_GROUP_DEPTH:
                return None
            real, groups = _group_output_input(link.from_node, link.from_socket), groups + (link.from_node,)
        else:
            return link.from_node, link.from_socket, groups
    return None


def value_socket(socket):
    """The socket whose own value an unlinked input has: the Group node's input outside when the input is linked
    to a Group Input (through any depth), else the input itself."""
    real, groups = _unwrap(socket), _context(socket)
    while real is not None and real.is_linked and groups:
        upstream = _through(real.links[0], groups)
        if not upstream:  # from another node (its own value is this socket's), or from nowhere
            break
        real, groups = upstream
    return real


def wrap_node(node, groups):
    return GroupNode(node, groups) if groups else node


class _Link:
    def __init__(self, from_node, from_socket):
        self.from_node, self.from_socket = from_node, from_socket


class GroupSocket:
    """A socket of a node inside a group: an input's link and own value are seen through the group's boundaries
    (an output's links are its own, within the group)."""

    def __init__(self, socket, groups):
        self.socket, self.groups = socket, groups

    @property
    def is_linked(self):
        return self.socket.is_linked if self.socket.is_output else resolve(self) is not None

    @property
    def links(self):
        if self.socket.is_output:
            return self.socket.links
        found = resolve(self)
        if found is None:
            return []
        node, out, groups = found
        return [_Link(wrap_node(node, groups), GroupSocket(out, groups) if groups else out)]

    @property
    def default_value(self):
        return self.socket.default_value if self.socket.is_output else value_socket(self).default_value

    def __getattr__(self, name):
        return getattr(self.socket, name)


class _Sockets:
    def __init__(self, sockets, groups):
        self._sockets, self._groups = sockets, groups

    def __getitem__(self, key):
        return GroupSocket(self._sockets[key], self._groups)

    def get(self, key, default=None):
        socket = self._sockets.get(key)
        return GroupSocket(socket, self._groups) if socket is not None else default

    def __iter__(self):
        return (GroupSocket(s, self._groups) for s in self._sockets)

    def __len__(self):
        return len(self._sockets)


class GroupNode:
    """A node inside a group: its sockets see through the group's boundaries; everything else is the node's."""

    def __init__(self, node, groups):
        self.node, self.groups = node, groups

    @property
    def inputs(self):
        return _Sockets(self.node.inputs, self.groups)

    @property
    def outputs(self):
        return _Sockets(self.node.outputs, self.groups)

    def __getattr__(self, name):
        return getattr(self.node, name)

    def __eq__(self, other):
        return isinstance(other, GroupNode) and other.node == self.node and other.groups == self.groups

    def __hash__(self):
        return hash((self.node.name, tuple(g.name for g in self.groups)))
