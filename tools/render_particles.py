#!/usr/bin/python3
"""Pictures of a Spall run: particles coloured by a point field, read from .vtu files with VTK.

    /usr/bin/python3 tools/render_particles.py RUN/d3plot_00000.vtu [MORE.vtu ...] \\
        --field effective_plastic_strain -o picture.png [--view xz|yz|xy|iso] [--cut] ...

Several files make panels side by side on one colour scale (e.g. before and after). Views:
  xz, yz, xy  the particles seen along the third axis, as discs of one particle spacing, drawn
              back to front so that the visible side is the near one (the viewer is at +z for xy,
              +x for yz, -y for xz); --cut leaves out the near half of the body (beyond its
              middle plane), showing the cut face.
  iso         a 3-D view from (1, -1, 0.7); --surface draws instead the body's surface as seed 000
              (Kayar) Figure 3 does: the level c = 1/2 of the colour field
              c(x) = sum_b V_b W(x - x_b, h_b) (seed 000 eq. 10, cubic spline of support 2 h_b),
              found by marching cubes (VTK's flying edges) on a grid of half a spacing, each
              triangle coloured by the field of the particle nearest to it.
Points where the field is NaN (docs/OUTPUT.md: the fill value of a point the field's formulation
does not own, e.g. the nodes of finite elements for a particle field) are drawn light grey.
--categories colours the field `category` (*SPALL_SPH_COLOUR_FIELD) as seed 000 Figure 4 does:
surface green, inner layer red, interior blue.
The particle volume V_b = m_b / rho_b is (h_b / CSLH)^3 while h follows the density
(h = CSLH (m / rho)^(1/3), docs/THEORY.md), so --cslh must be the deck's (default 1.2).

Rendering is matplotlib's (Agg, no display needed): Debian's VTK has no off-screen OpenGL
window without an X server. Needs python3-vtk9, python3-numpy and python3-matplotlib
(tools/setup.sh installs them); run it with /usr/bin/python3.
"""
import argparse
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy  # noqa: E402
import vtk  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from particle_files import median_spacing, point_locator, read_particles  # noqa: E402
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402

AXES = {"x": 0, "y": 1, "z": 2}
# Seed 000 Figure 4's colours for the field `category` (0 interior, 1 inner layer, 2 surface).
CATEGORIES = [("interior", "tab:blue"), ("inner layer", "tab:red"), ("surface", "tab:green")]
COMPONENTS = {"x": 0, "y": 1, "z": 2, "xx": 0, "yy": 1, "zz": 2, "xy": 3, "yz": 4, "zx": 5}


def point_field(grid, path, name, component):
    """The field's values per particle: one component, or the magnitude of a vector."""
    data = grid.GetPointData()
    array = data.GetArray(name)
    if array is None:
        present = " ".join(data.GetArrayName(i) for i in range(data.GetNumberOfArrays()))
        sys.exit(f"render_particles: {path}: no point field '{name}' (present: {present})")
    values = vtk_to_numpy(array).astype(float).reshape(grid.GetNumberOfPoints(), -1)
    if values.shape[1] == 1:
        return values[:, 0]
    if component is None:
        return numpy.linalg.norm(values, axis=1)
    index = COMPONENTS[component]
    if index >= values.shape[1]:
        sys.exit(f"render_particles: field '{name}' has {values.shape[1]} components, no '{component}'")
    return values[:, index]


def cubic_spline(q, h):
    """LS-DYNA's cubic B-spline of support 2h in 3-D (Monaghan & Lattanzio 1985)."""
    w = numpy.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, numpy.where(q < 2, 0.25 * (2 - q) ** 3, 0.0))
    return w / (math.pi * h**3)


def colour_field_surface(x, h, cslh, dx):
    """Triangles (n, 3, 3) of the level c = 1/2 of c(x) = sum_b V_b W(x - x_b, h_b)."""
    step = dx / 2
    volume = (h / cslh) ** 3
    reach = 2 * h.max()
    lower = x.min(axis=0) - reach - step
    dims = numpy.ceil((x.max(axis=0) + reach + step - lower) / step).astype(int) + 1
    c = numpy.zeros(dims[::-1])  # indexed [k, j, i], i fastest as VTK stores it
    base = numpy.floor((x - lower) / step).astype(int)
    m = int(math.ceil(reach / step))
    for dk in range(-m, m + 2):
        for dj in range(-m, m + 2):
            for di in range(-m, m + 2):
                cell = base + numpy.array([di, dj, dk])
                r = numpy.linalg.norm(lower + cell * step - x, axis=1)
                near = r < 2 * h
                numpy.add.at(c, (cell[near, 2], cell[near, 1], cell[near, 0]),
                             volume[near] * cubic_spline(r[near] / h[near], h[near]))
    image = vtk.vtkImageData()
    image.SetDimensions(*dims)
    image.SetOrigin(*lower)
    image.SetSpacing(step, step, step)
    image.GetPointData().SetScalars(numpy_to_vtk(c.ravel()))
    contour = vtk.vtkFlyingEdges3D()
    contour.SetInputData(image)
    contour.SetValue(0, 0.5)
    contour.Update()
    surface = contour.GetOutput()
    vertices = vtk_to_numpy(surface.GetPoints().GetData())
    polys = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return vertices[polys]


def nearest_values(x, values, points):
    """The value of the particle nearest to each of the points."""
    locator = point_locator(x)
    return numpy.array([values[locator.FindClosestPoint(p)] for p in points])


def draw_plane(ax, x, values, view, cut, dx, limits, norm, cmap, scale):
    a, b = AXES[view[0]], AXES[view[1]]
    c = 3 - a - b
    # The viewer sits on the side the page's normal e_a x e_b points to (+z for xy, +x for yz,
    # -y for xz): depth grows towards the viewer.
    toward_viewer = numpy.cross(numpy.eye(3)[a], numpy.eye(3)[b])[c]
    depth = toward_viewer * x[:, c]
    keep = depth <= 0.5 * (depth.min() + depth.max()) + 1e-9 * dx if cut else numpy.ones(len(x), bool)
    # Back to front, so that the near particles cover the far ones.
    order = numpy.argsort(depth[keep], kind="stable")
    xs, ys, vs = x[keep][order, a] * scale, x[keep][order, b] * scale, values[keep][order]
    ax.set_aspect("equal")
    ax.set_xlim((limits[0][a] - dx) * scale, (limits[1][a] + dx) * scale)
    ax.set_ylim((limits[0][b] - dx) * scale, (limits[1][b] + dx) * scale)
    ax.set_xlabel(view[0])
    ax.set_ylabel(view[1])
    return ax.scatter(xs, ys, c=vs, marker="o", cmap=cmap, norm=norm, linewidths=0, plotnonfinite=True)


def size_markers(ax, markers, diameter):
    """Markers of the given diameter in data units, from the axes' final size on the page."""
    points_per_unit = ax.get_window_extent().width / (ax.get_xlim()[1] - ax.get_xlim()[0]) * 72 / ax.figure.dpi
    markers.set_sizes([(diameter * points_per_unit) ** 2])


def draw_iso(ax, x, values, surface, h, cslh, dx, limits, norm, cmap, scale):
    if surface:
        triangles = colour_field_surface(x, h, cslh, dx)
        colours = cmap(norm(nearest_values(x, values, triangles.mean(axis=1))))
        # Lambert shading from a light behind the viewer, so that the shape reads.
        normals = numpy.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
        normals /= numpy.linalg.norm(normals, axis=1, keepdims=True) + 1e-300
        light = numpy.array([0.6, -0.7, 0.8])
        light /= numpy.linalg.norm(light)
        shade = 0.45 + 0.55 * numpy.abs(normals @ light)
        colours[:, :3] *= shade[:, None]
        ax.add_collection3d(Poly3DCollection(triangles * scale, facecolors=colours, linewidths=0))
    else:
        ax.scatter(x[:, 0] * scale, x[:, 1] * scale, x[:, 2] * scale, c=values, cmap=cmap, norm=norm,
                   s=4, depthshade=True, linewidths=0)
    # The surface lies about half a spacing outside the particles' centres.
    lo, hi = (limits[0] - dx) * scale, (limits[1] + dx) * scale
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo)
    ax.view_init(elev=25, azim=-50)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("vtu", nargs="+", help="one .vtu per panel")
    parser.add_argument("--field", required=True, help="point field to colour by (pressure, ...)")
    parser.add_argument("--component", choices=COMPONENTS, help="of a vector or tensor field (default: magnitude)")
    parser.add_argument("-o", "--output", required=True, help="the .png to write")
    parser.add_argument("--view", choices=["xz", "yz", "xy", "iso"], default="xz")
    parser.add_argument("--cut", action="store_true", help="xz/yz/xy: leave out the near half of the body")
    parser.add_argument("--surface", action="store_true", help="iso: the colour-field surface instead of particles")
    parser.add_argument("--cslh", type=float, default=1.2, help="the deck's *SECTION_SPH CSLH (for --surface)")
    parser.add_argument("--spacing", type=float,
                        help="particle spacing for the markers and the surface grid (default: the median "
                             "nearest-neighbour distance in the first file)")
    parser.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"), help="colour scale (default: data)")
    parser.add_argument("--scale", type=float, default=1.0, help="multiply lengths by this on the axes")
    parser.add_argument("--unit", default="", help="length unit shown on the axes, e.g. mm")
    parser.add_argument("--field-label", help="colour bar label (default: the field's name)")
    parser.add_argument("--labels", nargs="+", help="one title per panel")
    parser.add_argument("--title", help="title above all panels")
    parser.add_argument("--cmap", default="viridis")
    parser.add_argument("--categories", action="store_true",
                        help="colour the field `category` as seed 000 Figure 4 (surface green, inner red, interior blue)")
    parser.add_argument("--width", type=float, default=4.0, help="inches per panel")
    parser.add_argument("--height", type=float, default=4.0, help="inches (per panel with --stack)")
    parser.add_argument("--stack", action="store_true", help="panels one above the other (long bodies)")
    parser.add_argument("--dpi", type=int, default=100)
    parser.add_argument("--part", type=int, nargs="+", help="draw only the particles of these parts (part_id)")
    parser.add_argument("--box", type=float, nargs=6, metavar=("X0", "Y0", "Z0", "X1", "Y1", "Z1"),
                        help="draw only the particles inside this box (the deck's lengths): leaves out debris")
    args = parser.parse_args()
    if args.labels and len(args.labels) != len(args.vtu):
        sys.exit("render_particles: --labels needs one label per file")
    if args.surface and args.view != "iso":
        sys.exit("render_particles: --surface needs --view iso")

    frames = []
    for path in args.vtu:
        grid = read_particles(path, "render_particles")
        x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
        h = point_field(grid, path, "smoothing_length", None) if args.surface else None
        values = point_field(grid, path, args.field, args.component)
        if args.part:
            keep = numpy.isin(point_field(grid, path, "part_id", None), args.part)
            if not keep.any():
                sys.exit(f"render_particles: {path}: no particle of part(s) {args.part}")
            x, values, h = x[keep], values[keep], (h[keep] if h is not None else None)
        if args.box:
            keep = numpy.all((x >= args.box[:3]) & (x <= args.box[3:]), axis=1)
            x, values, h = x[keep], values[keep], (h[keep] if h is not None else None)
        frames.append((x, values, h))
    dx = args.spacing or median_spacing(frames[0][0])
    # One frame for all panels, so that they compare at one scale.
    limits = (numpy.min([x.min(axis=0) for x, _, _ in frames], axis=0),
              numpy.max([x.max(axis=0) for x, _, _ in frames], axis=0))
    if args.categories:
        if args.field != "category" or args.range:
            sys.exit("render_particles: --categories goes with --field category and no --range")
        low, high = -0.5, len(CATEGORIES) - 0.5
        cmap = matplotlib.colors.ListedColormap([colour for _, colour in CATEGORIES])
        norm = matplotlib.colors.BoundaryNorm(numpy.arange(len(CATEGORIES) + 1) - 0.5, len(CATEGORIES))
    else:
        low = min(numpy.nanmin(v) for _, v, _ in frames) if args.range is None else args.range[0]
        high = max(numpy.nanmax(v) for _, v, _ in frames) if args.range is None else args.range[1]
        norm = matplotlib.colors.Normalize(vmin=low, vmax=high if high > low else low + 1)
        # Points without the field (its fill value NaN: the nodes of finite elements, say) in grey.
        cmap = matplotlib.colormaps[args.cmap].with_extremes(bad="lightgrey")

    rows, columns = (len(frames), 1) if args.stack else (1, len(frames))
    fig = plt.figure(figsize=(args.width * columns + 1.2, args.height * rows), dpi=args.dpi, layout="constrained")
    axes, markers = [], []
    for k, (x, values, h) in enumerate(frames):
        projection = "3d" if args.view == "iso" else None
        ax = fig.add_subplot(rows, columns, k + 1, projection=projection)
        if args.view == "iso":
            draw_iso(ax, x, values, args.surface, h, args.cslh, dx, limits, norm, cmap, args.scale)
        else:
            markers.append(draw_plane(ax, x, values, args.view, args.cut, dx, limits, norm, cmap, args.scale))
        if args.unit:
            for axis in ("x", "y", "z"):
                setter = getattr(ax, f"set_{axis}label", None)
                label = getattr(ax, f"get_{axis}label", lambda: "")()
                if setter and label:
                    setter(f"{label} [{args.unit}]")
        if args.labels:
            ax.set_title(args.labels[k], fontsize=10)
        axes.append(ax)
    data_low = min(numpy.nanmin(v) for _, v, _ in frames)
    data_high = max(numpy.nanmax(v) for _, v, _ in frames)
    extend = {(False, False): "neither", (True, False): "min", (False, True): "max", (True, True): "both"}[
        (data_low < low, data_high > high)]
    bar = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes, shrink=0.9, extend=extend)
    bar.set_label(args.field_label or args.field + (f" {args.component}" if args.component else ""))
    if args.categories:
        bar.set_ticks(range(len(CATEGORIES)), labels=[name for name, _ in CATEGORIES])
    if args.title:
        fig.suptitle(args.title, fontsize=11)
    fig.canvas.draw()  # lays the figure out, so that the axes have their final size
    for ax, m in zip(axes, markers):
        size_markers(ax, m, dx * args.scale)
    fig.savefig(args.output, dpi=args.dpi, bbox_inches="tight")
    print(f"render_particles: wrote {args.output} ({len(frames)} panel(s), colour {low:.4g} .. {high:.4g}, "
          f"data {data_low:.4g} .. {data_high:.4g})")


if __name__ == "__main__":
    main()
