"""Links followed as Cycles 3.4 compiles a node tree (intern/cycles/blender/shader.cpp): a muted link, an invalid
one (Blender marks invalid a link that closes a cycle or joins sockets of types that do not connect) or one from or
to an unavailable socket is left out; a muted node and a reroute pass an input on to an output along Blender's
internal link (an output without one is unlinked), and an unlinked input they pass on reads 0 (Cycles' proxy's
value); node groups are inlined: a link from a Group node's output continues inside the group at its Group
Output, and a link from a Group Input continues at the Group node's input outside (its own value when nothing is
linked there).  Nested groups work the same way, to MAX_GROUP_DEPTH.

The exporter reads node trees through sockets (`is_linked`, `links[0].from_node`, `default_value`) and nodes
(`inputs[...]`, properties).  It reads every node wrapped (CyclesNode, CyclesSocket, wrap_node), carrying the
chain of Group nodes it sits in, so that those reads see the links Cycles follows."""

_GROUP, _GROUP_INPUT, _GROUP_OUTPUT, _REROUTE = "ShaderNodeGroup", "NodeGroupInput", "NodeGroupOutput", "NodeReroute"
MAX_GROUP_DEPTH = 16  # deeper groups: the link is treated as absent (too_deep_groups names them)
_MAX_HOPS = 64 * MAX_GROUP_DEPTH  # reroutes, muted nodes and group boundaries on one link's way


def _unwrap(socket):
    return socket.socket if isinstance(socket, CyclesSocket) else socket


def _context(socket):
    return socket.groups if isinstance(socket, CyclesSocket) else ()


# Each tree's links by the input they go into, built once per export (NodeSocket.links walks all the tree's links:
# reading it per input would make an export quadratic in the links).
_links_by_input = {}


def read_links_anew():
    """Forgets the trees' links read so far: each export starts with it (the trees may have changed since)."""
    _links_by_input.clear()


def _links_into(socket):
    if not socket.is_linked:
        return ()
    tree = socket.id_data
    index = _links_by_input.get(tree.as_pointer())
    if index is None:
        index = _links_by_input[tree.as_pointer()] = {}
        for link in tree.links:
            index.setdefault(link.to_socket.as_pointer(), []).append(link)
    return index.get(socket.as_pointer(), ())


def followed_link(socket):
    """The link into Blender input `socket` that Cycles keeps, or None."""
    for link in _links_into(socket):
        if link.is_valid and not link.is_muted and link.from_socket.enabled and link.to_socket.enabled:
            return link
    return None


def _passed_input(node, output):
    """The input a muted node or a reroute passes on to its `output`, or None."""
    if node.bl_idname == _REROUTE:
        return node.inputs[0]
    return next((link.from_socket for link in node.internal_links if link.to_socket == output), None)


def _group_output_input(group_node, output_socket):
    """The Group Output input inside `group_node`'s tree that its output `output_socket` shows."""
    tree = group_node.node_tree
    if tree is None:
        return None
    index = list(group_node.outputs).index(output_socket)
    outputs = [n for n in tree.nodes if n.bl_idname == _GROUP_OUTPUT]
    active = [n for n in outputs if getattr(n, "is_active_output", False)] or outputs
    return active[0].inputs[index] if active and index < len(active[0].inputs) else None


class _Zero:
    """The own value of an input a muted node or a reroute passes an unlinked input to: 0 (Cycles' proxy's)."""

    def __init__(self, socket):
        self.socket = socket

    @property
    def default_value(self):
        value = self.socket.default_value
        try:
            return tuple(0.0 for _ in value)
        except TypeError:
            return type(value)(0)


def trace(socket):
    """(node, output socket, groups) feeding input `socket` as Cycles links it, or None; and the socket whose own
    value the input has (when nothing feeds it, or when what does is not modelled).  The node is the real one,
    `groups` the chain of Group nodes it sits in."""
    real, groups = _unwrap(socket), _context(socket)
    value, passed = real, False
    for _ in range(_MAX_HOPS):
        link = followed_link(real)
        if link is None:
            break
        node = link.from_node
        if node.mute or node.bl_idname == _REROUTE:
            real, passed = _passed_input(node, link.from_socket), True
            if real is None:  # no internal link: the input is unlinked
                return None, value
        elif node.bl_idname == _GROUP_INPUT:
            index = list(node.outputs).index(link.from_socket)
            if not groups or index >= len(groups[-1].inputs):
                break
            real, groups = groups[-1].inputs[index], groups[:-1]
            value, passed = real, False
        elif node.bl_idname == _GROUP:
            if len(groups) >= MAX_GROUP_DEPTH:
                break
            real, groups = _group_output_input(node, link.from_socket), groups + (node,)
            if real is None:  # no Group Output: the group's output proxy is unlinked
                return None, _Zero(value)
            value, passed = real, False
        else:
            return (node, link.from_socket, groups), value
    return None, _Zero(value) if passed else value


def resolve(socket):
    return trace(socket)[0]


def too_deep_groups(tree, depth=0, deepest=None):
    """Names of the node groups of `tree` nested deeper than MAX_GROUP_DEPTH (their links are left out); each group
    looked into again only where it sits deeper than before (at most MAX_GROUP_DEPTH times)."""
    deepest = {} if deepest is None else deepest  # group -> the deepest level it was looked into at
    found = []
    for node in tree.nodes:
        group = node.node_tree if node.bl_idname == _GROUP else None
        if group is None or deepest.get(group.as_pointer(), -1) >= depth:
            continue
        deepest[group.as_pointer()] = depth
        if depth >= MAX_GROUP_DEPTH:
            found.append(group.name)
        else:
            found.extend(too_deep_groups(group, depth + 1, deepest))
    return found


def wrap_node(node, groups=()):
    return node if isinstance(node, CyclesNode) else CyclesNode(node, groups)


class _Link:
    def __init__(self, from_node, from_socket):
        self.from_node, self.from_socket = from_node, from_socket


class CyclesSocket:
    """A node's socket as Cycles links it: an input's link and own value are trace()'s (an output's links are its
    own)."""

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
        return [_Link(CyclesNode(node, groups), CyclesSocket(out, groups))]

    @property
    def default_value(self):
        return self.socket.default_value if self.socket.is_output else trace(self)[1].default_value

    def __getattr__(self, name):
        return getattr(self.socket, name)


class _Sockets:
    def __init__(self, sockets, groups):
        self._sockets, self._groups = sockets, groups

    def __getitem__(self, key):
        return CyclesSocket(self._sockets[key], self._groups)

    def get(self, key, default=None):
        socket = self._sockets.get(key)
        return CyclesSocket(socket, self._groups) if socket is not None else default

    def __iter__(self):
        return (CyclesSocket(s, self._groups) for s in self._sockets)

    def __len__(self):
        return len(self._sockets)


class CyclesNode:
    """A node (inside the Group nodes `groups`): its sockets are CyclesSockets; everything else is the node's."""

    def __init__(self, node, groups):
        self.node, self.groups = node, groups

    @property
    def inputs(self):
        return _Sockets(self.node.inputs, self.groups)

    @property
    def outputs(self):
        return _Sockets(self.node.outputs, self.groups)

    @property
    def key(self):
        """The node's identity in its material's inlined tree (a group's node once per Group node using it)."""
        return (self.node.as_pointer(), tuple(g.as_pointer() for g in self.groups))

    def __getattr__(self, name):
        return getattr(self.node, name)

    def __eq__(self, other):
        return isinstance(other, CyclesNode) and other.key == self.key

    def __hash__(self):
        return hash(self.key)


def own_value(socket):
    """A socket's own (default) value: a float, or a tuple of floats (a colour, a vector)."""
    value = socket.default_value
    try:
        return tuple(float(v) for v in value)
    except TypeError:
        return float(value)
