"""The small generated part the main-job tests take from Prepare surface to
a STEP of fitted patches (headless and GUI alike): a box with rounded edges
(every face smooth into the next, so the fit can close into a solid), with
one user strip around its middle and the weaving options that keep the run
short."""

TRIANGLES = 3000
SIZE = (20.0, 14.0, 10.0)
RADIUS = 3.0
# The user's strip: a belt around the box through the middle of its +x face.
USER_ANCHOR = (SIZE[0], SIZE[1] / 2, SIZE[2] / 2, 0.0, 0.0, 1.0)
WEAVE_OPTIONS = {"max_strips": 8, "budget": 60.0, "refine": False}


def shape():
    import Part
    box = Part.makeBox(*SIZE)
    return box.makeFillet(RADIUS, box.Edges)


def make(doc, name="RoundedBox"):
    part = doc.addObject("Part::Feature", name)
    part.Shape = shape()
    doc.recompute()
    return part
