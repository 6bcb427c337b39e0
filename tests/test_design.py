"""Design files (design.md): validation, round trip, unknown keys kept."""
import json

import pytest

import stripweave as sw
from stripweave.design import DEFAULT_OPTIONS, Design


def sample():
    return {"format": "stripweave-design", "version": 1,
            "model": {"path": "part.step", "bbox_diagonal": 12.5},
            "options": {"k": 4, "boundary": "trimmed", "vendor_option": [1, 2]},
            "strips": [{"anchors": [{"point": [1, 2, 3], "direction": [0, 0, 1], "label": "a"},
                                    {"point": [4, 5, 6], "direction": None}],
                        "closed": True, "colour": "#ff0000"}],
            "history": {"created_by": "a newer tool"}}


def test_round_trip_keeps_everything_including_unknown_keys(tmp_path):
    path = tmp_path / "design.json"
    Design.from_dict(sample()).save(path)
    again = json.loads(path.read_text())
    want = sample()
    want["options"] = {**DEFAULT_OPTIONS, **want["options"]}
    assert again == want
    d = Design.load(path)
    assert d.anchor_lists() == [[[1.0, 2.0, 3.0, 0.0, 0.0, 1.0], [4.0, 5.0, 6.0]]]
    assert d.loop_options()["boundary"] == "trimmed"


def test_only_format_version_and_strips_are_required():
    d = Design.from_dict({"format": "stripweave-design", "version": 1, "strips": []})
    assert d.options == DEFAULT_OPTIONS and d.strips == []


def test_editing():
    d = Design()
    d.add_strip([(0, 0, 0, 1, 0, 0)])
    d.add_strip([(1, 1, 1)])
    d.edit_strip(0, [(2, 2, 2)])
    d.remove_strip(1)
    assert d.anchor_lists() == [[[2.0, 2.0, 2.0]]]


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d.update(format="something-else"), "'format'"),
    (lambda d: d.update(version=99), "newer"),
    (lambda d: d.pop("strips"), "'strips'"),
    (lambda d: d["strips"][0].update(anchors=[]), "strip 1"),
    (lambda d: d["strips"][0]["anchors"][0].update(point=[1, 2]), "strip 1, anchor 1"),
    (lambda d: d["strips"][0]["anchors"][1].update(direction=[0, 0, 0]), "must not be zero"),
    (lambda d: d["strips"][0]["anchors"][0].update(point=[1, "x", 3]), "three numbers"),
    (lambda d: d["options"].update(boundary="sideways"), "boundary"),
])
def test_bad_design_files_name_the_problem(mutate, message):
    data = sample()
    mutate(data)
    with pytest.raises(sw.InputError, match=message):
        Design.from_dict(data)


def test_broken_json_is_a_clear_error(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"format": "stripweave-design", "version": 1, "strips": [')
    with pytest.raises(sw.InputError, match="not valid JSON"):
        Design.load(path)


def test_a_failed_save_leaves_the_old_file(tmp_path):
    path = tmp_path / "design.json"
    Design.from_dict(sample()).save(path)
    before = path.read_text()
    d = Design.from_dict(sample())
    d.extra["bad"] = object()  # not JSON-serializable
    with pytest.raises(TypeError):
        d.save(path)
    assert path.read_text() == before


def test_removing_strips_renumbers_their_images():
    """A strip's symmetric images name it ("image_of"): removing strips leaves an image of a
    removed strip an image no longer, and a later image naming its original anew."""
    from stripweave.design import Design, Strip
    strips = [Strip([[float(i), 0.0, 0.0]]) for i in range(5)]
    strips[1].extra["image_of"] = 0
    strips[3].extra["image_of"] = 2
    strips[4].extra["image_of"] = 2
    d = Design(strips)
    d.remove_strip(0)
    assert [s.extra.get("image_of") for s in d.strips] == [None, None, 1, 1]
    d.remove_strips(0, 2)
    assert [s.extra.get("image_of") for s in d.strips] == [None, None]
