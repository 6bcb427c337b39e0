"""Text drawn into numpy images: a 5 x 8 bitmap font for printable ASCII (issue 16).

    text_mask(text, scale=2) -> bool array (h, w): True where the text's ink is
    text_size(text, scale=2) -> (w, h) in pixels
    draw_text(image, text, x, y, colour, scale=2) -> (w, h); ink written into image (H, W, 3)

The preview pictures need labels and a legend, and the renderer has no dependency beyond numpy
(no font library, no display): so the glyphs are written out here. Each glyph is 5 columns by 8
rows; rows 0 to 6 hold capitals and digits (row 6 is the baseline), row 7 the descenders of
g, j, p, q and y. A character cell is 6 x 10 (one column and two rows of space), scaled by an
integer `scale` (pixel replication: crisp at every size, no anti-aliasing to blur it). Text is
one line; characters without a glyph draw as '?'. (x, y) is the top left corner of the first
cell, in pixels; ink outside the image is clipped.
"""
import numpy as np

CELL_W, CELL_H = 6, 10
GLYPH_W, GLYPH_H = 5, 8

# One glyph a line: the character, then its rows top to bottom ('#' ink, '.' paper); rows not
# given (7 rows: no descender) are paper.
_FONT = r"""
0 .###. #...# #..## #.#.# ##..# #...# .###.
1 ..#.. .##.. ..#.. ..#.. ..#.. ..#.. .###.
2 .###. #...# ....# ...#. ..#.. .#... #####
3 ##### ...#. ..#.. ...#. ....# #...# .###.
4 ...#. ..##. .#.#. #..#. ##### ...#. ...#.
5 ##### #.... ####. ....# ....# #...# .###.
6 ..##. .#... #.... ####. #...# #...# .###.
7 ##### ....# ...#. ..#.. .#... .#... .#...
8 .###. #...# #...# .###. #...# #...# .###.
9 .###. #...# #...# .#### ....# ...#. .##..
A .###. #...# #...# ##### #...# #...# #...#
B ####. #...# #...# ####. #...# #...# ####.
C .###. #...# #.... #.... #.... #...# .###.
D ###.. #..#. #...# #...# #...# #..#. ###..
E ##### #.... #.... ####. #.... #.... #####
F ##### #.... #.... ####. #.... #.... #....
G .###. #...# #.... #.### #...# #...# .####
H #...# #...# #...# ##### #...# #...# #...#
I .###. ..#.. ..#.. ..#.. ..#.. ..#.. .###.
J ..### ...#. ...#. ...#. ...#. #..#. .##..
K #...# #..#. #.#.. ##... #.#.. #..#. #...#
L #.... #.... #.... #.... #.... #.... #####
M #...# ##.## #.#.# #.#.# #...# #...# #...#
N #...# #...# ##..# #.#.# #..## #...# #...#
O .###. #...# #...# #...# #...# #...# .###.
P ####. #...# #...# ####. #.... #.... #....
Q .###. #...# #...# #...# #.#.# #..#. .##.#
R ####. #...# #...# ####. #.#.. #..#. #...#
S .#### #.... #.... .###. ....# ....# ####.
T ##### ..#.. ..#.. ..#.. ..#.. ..#.. ..#..
U #...# #...# #...# #...# #...# #...# .###.
V #...# #...# #...# #...# #...# .#.#. ..#..
W #...# #...# #...# #.#.# #.#.# #.#.# .#.#.
X #...# #...# .#.#. ..#.. .#.#. #...# #...#
Y #...# #...# .#.#. ..#.. ..#.. ..#.. ..#..
Z ##### ....# ...#. ..#.. .#... #.... #####
a ..... ..... .###. ....# .#### #...# .####
b #.... #.... #.##. ##..# #...# #...# ####.
c ..... ..... .###. #.... #.... #...# .###.
d ....# ....# .##.# #..## #...# #...# .####
e ..... ..... .###. #...# ##### #.... .###.
f ..##. .#..# .#... ###.. .#... .#... .#...
g ..... ..... .#### #...# #...# .#### ....# .###.
h #.... #.... #.##. ##..# #...# #...# #...#
i ..#.. ..... .##.. ..#.. ..#.. ..#.. .###.
j ...#. ..... ..##. ...#. ...#. ...#. #..#. .##..
k #.... #.... #..#. #.#.. ##... #.#.. #..#.
l .##.. ..#.. ..#.. ..#.. ..#.. ..#.. .###.
m ..... ..... ##.#. #.#.# #.#.# #.#.# #.#.#
n ..... ..... #.##. ##..# #...# #...# #...#
o ..... ..... .###. #...# #...# #...# .###.
p ..... ..... ####. #...# #...# ####. #.... #....
q ..... ..... .#### #...# #...# .#### ....# ....#
r ..... ..... #.##. ##..# #.... #.... #....
s ..... ..... .###. #.... .###. ....# ####.
t .#... .#... ###.. .#... .#... .#..# ..##.
u ..... ..... #...# #...# #...# #..## .##.#
v ..... ..... #...# #...# #...# .#.#. ..#..
w ..... ..... #...# #...# #.#.# #.#.# .#.#.
x ..... ..... #...# .#.#. ..#.. .#.#. #...#
y ..... ..... #...# #...# #...# .#### ....# .###.
z ..... ..... ##### ...#. ..#.. .#... #####
! ..#.. ..#.. ..#.. ..#.. ..#.. ..... ..#..
" .#.#. .#.#. .#.#. ..... ..... ..... .....
# .#.#. .#.#. ##### .#.#. ##### .#.#. .#.#.
$ ..#.. .#### #.#.. .###. ..#.# ####. ..#..
% ##... ##..# ...#. ..#.. .#... #..## ...##
& .##.. #..#. #.#.. .#... #.#.# #..#. .##.#
' ..#.. ..#.. .#... ..... ..... ..... .....
( ...#. ..#.. .#... .#... .#... ..#.. ...#.
) .#... ..#.. ...#. ...#. ...#. ..#.. .#...
* ..... ..#.. #.#.# .###. #.#.# ..#.. .....
+ ..... ..#.. ..#.. ##### ..#.. ..#.. .....
, ..... ..... ..... ..... .##.. ..#.. .#...
- ..... ..... ..... ##### ..... ..... .....
. ..... ..... ..... ..... ..... .##.. .##..
/ ..... ....# ...#. ..#.. .#... #.... .....
: ..... .##.. .##.. ..... .##.. .##.. .....
; ..... .##.. .##.. ..... .##.. ..#.. .#...
< ...#. ..#.. .#... #.... .#... ..#.. ...#.
= ..... ..... ##### ..... ##### ..... .....
> .#... ..#.. ...#. ....# ...#. ..#.. .#...
? .###. #...# ....# ...#. ..#.. ..... ..#..
@ .###. #...# ....# .##.# #.#.# #.#.# .###.
[ .###. .#... .#... .#... .#... .#... .###.
\ ..... #.... .#... ..#.. ...#. ....# .....
] .###. ...#. ...#. ...#. ...#. ...#. .###.
^ ..#.. .#.#. #...# ..... ..... ..... .....
_ ..... ..... ..... ..... ..... ..... #####
` .#... ..#.. ...#. ..... ..... ..... .....
{ ...#. ..#.. ..#.. .#... ..#.. ..#.. ...#.
| ..#.. ..#.. ..#.. ..#.. ..#.. ..#.. ..#..
} .#... ..#.. ..#.. ...#. ..#.. ..#.. .#...
~ ..... ..... .#... #.#.# ...#. ..... .....
"""


def _parse(table):
    """{character: bool array (GLYPH_H, GLYPH_W)} from the table above."""
    glyphs = {" ": np.zeros((GLYPH_H, GLYPH_W), bool)}
    for line in table.strip("\n").split("\n"):
        char, rows = line[0], line[2:].split()
        g = np.zeros((GLYPH_H, GLYPH_W), bool)
        for r, row in enumerate(rows):
            g[r] = [c == "#" for c in row]
        glyphs[char] = g
    return glyphs


GLYPHS = _parse(_FONT)


def text_size(text, scale=2):
    """(width, height) in pixels of one line of text: whole cells, the last column of space
    and the two rows under the descenders included."""
    return len(text) * CELL_W * scale, CELL_H * scale


def text_mask(text, scale=2):
    """Where the text's ink is: a bool array (CELL_H * scale, len(text) * CELL_W * scale)."""
    cells = np.zeros((CELL_H, max(len(text), 0) * CELL_W), bool)
    for i, char in enumerate(text):
        cells[1:1 + GLYPH_H, i * CELL_W:i * CELL_W + GLYPH_W] = GLYPHS.get(char, GLYPHS["?"])
    return np.repeat(np.repeat(cells, scale, axis=0), scale, axis=1)


def draw_text(image, text, x, y, colour, scale=2):
    """Write the text's ink in `colour` into image (H, W, 3; any dtype colour fits) with the
    top left of its first cell at pixel (x, y). Returns the text's (width, height)."""
    mask = text_mask(text, scale)
    H, W = image.shape[:2]
    x, y = int(round(x)), int(round(y))
    x0, y0 = max(x, 0), max(y, 0)
    x1, y1 = min(x + mask.shape[1], W), min(y + mask.shape[0], H)
    if x1 > x0 and y1 > y0:
        region = image[y0:y1, x0:x1]
        region[mask[y0 - y:y1 - y, x0 - x:x1 - x]] = colour
    return mask.shape[1], mask.shape[0]
