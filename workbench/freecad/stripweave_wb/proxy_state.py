"""What the document-object proxies and view providers of the main job
share: their saved state (the type only, or nothing: the results live in
the properties and the Shape), and adding properties only where missing (a
document saved by an older version gains the new ones on restore)."""


class TypeOnlyState:
    """A proxy whose saved state is its ``TYPE_NAME`` (set as ``Type``);
    ``_result`` (a cache) starts empty after a restore."""

    TYPE_NAME = ""
    _result = None

    def __getstate__(self):
        return {"Type": self.TYPE_NAME, "version": 1}

    def __setstate__(self, state):
        self.Type = self.TYPE_NAME
        self._result = None
        return None

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        return self.__setstate__(state)


class StatelessViewProvider:
    """A view provider that saves nothing; ``self.Object`` once attached."""

    ICON = ""

    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        from . import icon_path
        return icon_path(self.ICON)

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None


def property_adder(obj):
    """``add(type, name, group, tip, attr=0, read_only=False, hidden=False)``
    that adds the property to ``obj`` unless it has it; True if added."""
    have = set(obj.PropertiesList)

    def add(ptype, name, group, tip, attr=0, read_only=False, hidden=False):
        if name in have:
            return False
        obj.addProperty(ptype, name, group, tip, attr, read_only, hidden)
        return True
    return add
