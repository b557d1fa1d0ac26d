// Type declarations of surfaced.mjs, written by hand after api/openapi.json (tests/clients/client_drift_test.py
// checks that every operation has a method and that each options type names exactly the API's options).
//
// Conventions: one `...Options` interface per operation, one property per line; options not given are not sent
// (the server applies its default, noted with @default). The output options come as `output` or flattened.

/** The OpenAPI info.version of the surfaced API this client was made for. */
export declare const API_VERSION: string;

/** Media type per mesh file extension the service reads. */
export declare const MESH_MEDIA_TYPES: {
  obj: 'model/obj'; off: 'model/off'; ply: 'application/ply'; stl: 'model/stl'; glb: 'model/gltf-binary';
  gltf: 'model/gltf+json';
};

/** Whether a server implementing API `serverVersion` serves a client made for `clientVersion` (default
 *  API_VERSION): the same major version and a minor version at least the client's; before 1.0, the same minor. */
export declare function isCompatible(serverVersion: string, clientVersion?: string): boolean;

// ---- values --------------------------------------------------------------------------------------------------------

export type Vec2 = [number, number] | number[];
export type Vec3 = [number, number, number] | number[];
/** A 2D or 3D point of a curve. */
export type Point = Vec2 | Vec3;
/** [[xmin, ymin, zmin], [xmax, ymax, zmax]] */
export type Bounds = [Vec3, Vec3] | Vec3[];
/** File bytes or text for an upload. */
export type BodyData = Uint8Array | ArrayBuffer | Blob | string;
/** A node of an implicit scene ({op: 'sphere', radius: 1}); nodes nest through arg / args, see the OpenAPI
 *  document's ImplicitScene and docs/implicit.md. */
export type ImplicitScene = { op?: string; ref?: string; id?: string; [member: string]: unknown };

export type Scheme = 'catmull-clark' | 'loop';
export type Boundary = 'edge-only' | 'edge-and-corner' | 'none';
export type CreaseMethod = 'uniform' | 'chaikin';
export type TriangleRule = 'catmark' | 'smooth';
export type UvInterpolation = 'none' | 'corners-only' | 'corners-plus1' | 'corners-plus2' | 'boundaries' | 'all';
export type LoopWeights = 'loop' | 'warren';
export type OutputFormat = 'glb' | 'gltf' | 'obj' | 'ply' | 'json' | 'stl' | 'off';
export type Compression = 'draco' | 'none';
export type RepairMode = 'auto' | 'none';
export type RemeshSmoothing = 'tangential' | 'laplacian' | 'none';
export type ImplicitMode = 'uniform' | 'adaptive';
export type TessellateFormat = OutputFormat | 'patches';
export type PatchSampleFormat = OutputFormat | 'patches';
export type PointcloudFormat = 'glb' | 'gltf' | 'ply' | 'json';
export type PoissonBoundary = 'neumann' | 'dirichlet';
export type NormalEstimation = 'auto' | 'always' | 'never';
export type CurvesFormat = 'json' | 'glb' | 'gltf';
export type KnotVector = 'clamped' | 'uniform' | 'closed';

export interface Mesh {
  positions: Vec3[];
  /** vertex indices, 3 or more per face */
  faces: number[][];
  /** vertex normals, one per position (the JSON output writes them unless normals is false) */
  normals?: Vec3[];
  uvs?: Vec2[];
  /** per face, one index into uvs per corner */
  uv_faces?: number[][];
}

/** Output options of a JSON request; a file upload sends them as query parameters. */
export interface Output<F extends string = OutputFormat> {
  /** @default 'glb' */
  format?: F;
  /** GLB/glTF. @default 'draco' */
  compression?: Compression;
  /** Draco position bits. @default 14 */
  quantize_position?: number;
  /** write vertex normals (glb, gltf, obj, ply, json; not with stl or off). @default true */
  normals?: boolean;
}

export interface Crease { edge: [number, number] | number[]; /** 10 or more: infinitely sharp */ sharpness: number }
export interface Corner { vertex: number; sharpness: number }
export interface Patch {
  /** [m, n]: degrees in u and v, 1..15 */
  degree: [number, number] | number[];
  /** (m+1)(n+1) control points, u varying fastest */
  points: Vec3[];
  /** one weight > 0 per control point: a rational patch */
  weights?: number[];
}
export interface Ray { origin: Vec3; direction: Vec3 }
export interface EstimateNormals { /** 3..256. @default 16 */ k?: number }
export interface Sample {
  count: number;
  mesh?: Mesh;
  scene?: ImplicitScene;
  /** required with scene */
  bounds?: Bounds;
  /** @default 1 */
  seed?: number;
}
export interface Derivatives { t: number[]; order: number }
export interface Tolerance { tolerance: number }
export interface ChainPiece { points: Point[]; weights?: number[] }
export interface Chain { pieces: ChainPiece[]; closed?: boolean }
export interface BSpline {
  degree: number;
  points: Point[];
  weights?: number[];
  /** points + degree + 1 non-decreasing knots */
  knots?: number[];
  /** @default 'clamped' */
  knot_vector?: KnotVector;
}
export interface Continuity { position_tolerance?: number; angle_tolerance?: number; derivative_tolerance?: number }
export interface EnforceC1 { mode?: 'C1' | 'G1'; side?: 'left' | 'right' | 'both'; joints?: number[] }
export interface InsertKnot { u: number; times?: number }
/** A B-spline/NURBS surface: count_u = knots_u.length - p - 1 control points along u, u varying fastest. */
export interface BSplineSurface {
  /** [p, q]: degrees in u and v, 1..15 */
  degree: [number, number] | number[];
  knots_u: number[];
  knots_v: number[];
  points: number[][];
  /** one weight > 0 per control point: a NURBS surface */
  weights?: number[];
}
/** A 2D B-spline/NURBS curve in a surface's (u, v); without knots, clamped uniform ones over [0, 1] (a Bezier curve). */
export interface TrimCurve {
  /** 1..15 */
  degree: number;
  points: number[][];
  knots?: number[];
  weights?: number[];
}
/** Trim loops: one outer loop (none: the whole domain) and holes, each a list of curves end to start. */
export interface SurfaceTrim {
  outer?: TrimCurve[];
  holes?: TrimCurve[][];
}
/** A surface of POST /tessellate; with trim, a trimmed surface (tessellated within tolerance, which it needs). */
export interface TessellateSurface extends BSplineSurface {
  trim?: SurfaceTrim;
}
export interface CurvesOutput { format?: CurvesFormat; compression?: 'none' }

// ---- option types, one per operation -------------------------------------------------------------------------------

/** Input of the mesh operations: a JSON mesh, or a file (OBJ, OFF, PLY, STL, GLB, glTF) with its media type. */
export interface MeshInput {
  mesh?: Mesh;
  data?: BodyData;
  /** see MESH_MEDIA_TYPES. @default 'application/octet-stream' */
  contentType?: string;
}

/** The output options, as `output` or flattened. */
export interface OutputOptions<F extends string = OutputFormat> {
  output?: Output<F>;
  /** @default 'glb' */
  format?: F;
  /** @default 'draco' */
  compression?: Compression;
  /** @default 14 */
  quantize_position?: number;
  /** not with stl or off. @default true */
  normals?: boolean;
}

export interface SubdivideOptions extends MeshInput, OutputOptions<OutputFormat> {
  /** @default 'catmull-clark' */
  scheme?: Scheme;
  /** 0..8. @default 1 */
  levels?: number;
  /** instead of levels: triangles within this distance (model units) of the Catmull-Clark limit surface; excludes
   *  levels and target_faces */
  tolerance?: number;
  /** with tolerance, at least 0 and below 1: vertices move off the limit surface towards its convex side by
   *  straddle x tolerance where it curves one way, so the surface crosses the triangles (still within the
   *  tolerance; fewer triangles); 0: every vertex on the surface. @default 0.45 */
  straddle?: number;
  /** the largest level (up to levels, if given) whose output has at most this many faces */
  target_faces?: number;
  /** default: the OBJ `t interpolateboundary` tag, else 'edge-only' */
  boundary?: Boundary;
  /** @default 'uniform' */
  crease_method?: CreaseMethod;
  /** @default 'catmark' */
  triangle_rule?: TriangleRule;
  /** @default 'corners-plus1' */
  uv_interpolation?: UvInterpolation;
  /** @default 'loop' */
  loop_weights?: LoopWeights;
  /** @default false */
  limit_surface?: boolean;
  /** 1 or 2: a second thread for large levels and, with tolerance, for half of the faces' planning (the same
   *  mesh). @default 1 */
  threads?: number;
  /** JSON only */
  creases?: Crease[];
  /** JSON only */
  corners?: Corner[];
  /** JSON only: indices of faces that are holes */
  holes?: number[];
}

export interface SimplifyOptions extends MeshInput, OutputOptions<OutputFormat> {
  target_faces?: number;
  /** in (0, 1] */
  ratio?: number;
  /** largest symmetric Hausdorff distance to the input, model units */
  max_error?: number;
  /** @default false */
  lock_border?: boolean;
  /** 0..1. @default 0 */
  restore_volume?: number;
  /** 1 or 2. @default 1 */
  threads?: number;
  /** @default false */
  report_error?: boolean;
  /** vertices kept in place and never removed */
  locked_vertices?: number[];
  /** @default 'auto' */
  repair?: RepairMode;
}

export interface RemeshOptions extends MeshInput, OutputOptions<OutputFormat> {
  /** default: the input's mean edge length */
  edge_length?: number;
  /** 0..100. @default 10 */
  iterations?: number;
  /** degrees, 0..180 (180: no features). @default 60 */
  feature_angle?: number;
  /** boundary vertices stay on the input's border (moving an open mesh's border shrinks it). @default true */
  lock_border?: boolean;
  /** @default 'tangential' */
  smoothing?: RemeshSmoothing;
  /** @default 'auto' */
  repair?: RepairMode;
}

export interface RepairOptions extends MeshInput, OutputOptions<OutputFormat> {
  /** @default 0 */
  weld_tolerance?: number;
  /** @default true */
  orient?: boolean;
  /** @default 0 */
  min_component_faces?: number;
  /** 0..10000. @default 0 */
  max_hole_edges?: number;
}

export interface TessellateOptions extends OutputOptions<TessellateFormat> {
  patches?: Patch[];
  /** B-spline/NURBS surfaces, tessellated through their Bezier patches; trimmed ones with trim */
  surfaces?: TessellateSurface[];
  /** geomview BEZ/BBP text */
  bez?: string;
  /** a BEZ file or an OBJ with free-form bezier or bspline surfaces */
  data?: BodyData;
  contentType?: string;
  /** guaranteed chord tolerance, model units (excludes segments) */
  tolerance?: number;
  /** 1..256. @default 8 */
  segments?: number;
}

export interface PatchSampleOptions {
  /** the ETag of an earlier answer: an unchanged one has status 304 */
  etag?: string;
  tolerance?: number;
  /** @default 8 */
  segments?: number;
  /** 'patches': the control points. @default 'glb' */
  format?: PatchSampleFormat;
  /** @default 'draco' */
  compression?: Compression;
  /** @default 14 */
  quantize_position?: number;
  /** @default true */
  normals?: boolean;
}

export interface CurvesOptions {
  /** one Bezier curve (2D or 3D) */
  points?: Point[];
  weights?: number[];
  chain?: Chain;
  /** SVG path data */
  svg?: string;
  bspline?: BSpline;
  evaluate?: number[];
  derivatives?: Derivatives;
  curvature?: number[];
  split?: number;
  elevate?: number;
  bounding_box?: boolean;
  length?: Tolerance;
  closest?: Point;
  tessellate?: Tolerance;
  continuity?: boolean | Continuity;
  enforce_c1?: EnforceC1;
  to_bezier?: boolean;
  insert_knot?: InsertKnot;
  output?: CurvesOutput;
}

export interface SurfacesOptions {
  surface: BSplineSurface;
  /** [u, v] in the domain: position, du, dv, normal */
  evaluate?: number[][];
  /** [u, v]: position and partial derivatives to order 2 */
  derivatives?: number[][];
  /** points: the global closest point on the surface to each */
  closest?: number[][];
  insert_knot?: { direction: 'u' | 'v'; value: number; times?: number };
  elevate?: { direction: 'u' | 'v'; times?: number };
  to_bezier?: boolean;
  bounding_box?: boolean;
}

export interface ImplicitQueryOptions {
  scene: ImplicitScene;
  points?: Vec3[];
  rays?: Ray[];
  /** @default 1e-6 */
  tolerance?: number;
  /** @default 100 */
  max_distance?: number;
  /** @default 1000 */
  max_steps?: number;
}

/** base64 of packed little-endian numbers, the items one after another */
export type PackedNumbers = { float32: string } | { float64: string };

export interface MeshQueryOptions {
  mesh: Mesh;
  points?: Vec3[] | PackedNumbers;
  /** [ox, oy, oz, dx, dy, dz]: origin, then a non-zero direction */
  rays?: number[][] | PackedNumbers;
  /** the point answers; absent: all four */
  want?: ('inside' | 'winding_number' | 'distance' | 'closest')[];
  winding?: { exact?: boolean; accuracy?: number };
  /** answers as JSON numbers, or every array as base64 of packed little-endian values. @default 'json' */
  encoding?: 'json' | 'float32' | 'float64';
}

/** A parametric point: a base face and (u, v) in its domain (Bfr's: [0, 1]^2 on a quad; an N-gon's N quad sub-face
 *  tiles [x, x + 1/2] x [y, y + 1/2]). */
export interface LimitPoint { face: number; uv: [number, number] | number[] }

export interface LimitEvaluateOptions {
  mesh: Mesh;
  /** or packed: base64 of (face, u, v) triples */
  points: LimitPoint[] | PackedNumbers;
  /** @default 'catmull-clark' */
  scheme?: Scheme;
  /** default: 'edge-only' */
  boundary?: Boundary;
  /** @default 'uniform' */
  crease_method?: CreaseMethod;
  /** @default 'catmark' */
  triangle_rule?: TriangleRule;
  /** @default 'corners-plus1' */
  uv_interpolation?: UvInterpolation;
  creases?: Crease[];
  corners?: Corner[];
  /** indices of faces that are holes */
  holes?: number[];
  /** 1, or 2 for duu, duv, dvv too. @default 1 */
  derivatives?: number;
  /** answers as JSON, or each member as one base64 array of packed little-endian values. @default 'json' */
  encoding?: 'json' | 'float32' | 'float64';
}

export interface LimitPointAnswer {
  position: number[]; du: number[]; dv: number[]; normal: number[];
  duu?: number[]; duv?: number[]; dvv?: number[];
  /** the limit of the mesh's texture coordinates, when it has them */
  uv?: number[];
  /** false within 2^-24 of an extraordinary vertex */
  exact: boolean;
}

/** With `encoding` float32 or float64, `points` is one base64 string per member instead. */
export interface LimitEvaluateAnswer {
  encoding?: 'float32' | 'float64';
  points: LimitPointAnswer[] | Record<string, string>;
}

export interface ImplicitGridOptions {
  /** exactly one of mesh and scene */
  mesh?: Mesh;
  scene?: ImplicitScene;
  /** the grid spacing, > 0 */
  voxel_size: number;
  /** voxels, 1..64; nodes beyond hold +-band * voxel_size. @default 3 */
  band?: number;
  /** required with a scene; a mesh's box grown by band + 1 voxels when absent */
  bounds?: Bounds;
}

/** A level_set scene node: values[i + nx (j + ny k)] at origin + (i, j, k) * spacing. */
export interface LevelSetNode {
  op: 'level_set';
  dims: [number, number, number];
  origin: Vec3;
  spacing: number;
  values: number[];
}

export interface ImplicitMeshOptions {
  scene: ImplicitScene;
  bounds: Bounds;
  /** 2..65536 (excludes cell_size). @default 64 */
  resolution?: number;
  cell_size?: number;
  /** @default 'uniform' */
  mode?: ImplicitMode;
  /** adaptive mode. @default 0 */
  simplify_tolerance?: number;
  /** GLB/glTF with output.normals: split normals at edges sharper than this (degrees). @default 40 */
  crease_angle?: number;
  output?: Output<OutputFormat>;
}

export interface PointcloudOptions {
  points?: Vec3[];
  /** with JSON points: their normals; a boolean is the output option (false: no normals in the output) */
  normals?: Vec3[] | boolean;
  /** [r, g, b] or [r, g, b, a] in 0..1 per point */
  colors?: number[][];
  sample?: Sample;
  /** a PLY, OBJ, XYZ, GLB or glTF file */
  data?: BodyData;
  contentType?: string;
  /** @default false */
  estimate_normals?: boolean | EstimateNormals;
  /** 3..256. @default 16 */
  k?: number;
  output?: Output<PointcloudFormat>;
  /** @default 'glb' */
  format?: PointcloudFormat;
  /** @default 'draco' */
  compression?: Compression;
  /** @default 14 */
  quantize_position?: number;
}

export interface ReconstructOptions {
  points?: Vec3[];
  /** with JSON points: their normals (outward); a boolean is the output option (false: no vertex normals) */
  normals?: Vec3[] | boolean;
  /** [r, g, b] or [r, g, b, a] in 0..1 per point */
  colors?: number[][];
  /** a PLY, OBJ, XYZ, GLB or glTF file */
  data?: BodyData;
  contentType?: string;
  /** finest octree level, 2..10 (the server's grid-cell budget refuses 9 and 10 by default). @default 8 */
  depth?: number;
  /** screening weight, 0 or more (0: unscreened). @default 4 */
  point_weight?: number;
  /** samples per cell on the splatting level of a point, positive. @default 1.5 */
  samples_per_node?: number;
  /** @default 'neumann' */
  boundary?: PoissonBoundary;
  /** bounding cube side over the bounding box's largest side, 1..100. @default 1.1 */
  scale?: number;
  /** move each vertex onto the points' tangent planes after meshing (false: the iso-surface as meshed). @default true */
  fit_to_samples?: boolean;
  /** weight each point by its PLY confidence, else its normal length. @default false */
  confidence?: boolean;
  /** estimate normals when the cloud has none (auto), always, or never. @default 'auto' */
  estimate_normals?: NormalEstimation;
  /** neighbours for normal estimation, 3..256. @default 16 */
  k?: number;
  /** cut the surface where the sampling density is below this, on the octree-depth scale (0: keep all). @default 0 */
  trim?: number;
  /** with trim: smaller pieces are removed, smaller low regions kept, as a fraction of the area. @default 0.001 */
  island_area?: number;
  /** carry the colours of the points to the vertices (glb, gltf, ply, obj, json); unset: when the cloud has colours */
  vertex_colors?: boolean;
  /** 1 or 2: a second thread for the large levels (the same mesh). @default 1 */
  threads?: number;
  output?: Output<OutputFormat>;
  /** @default 'glb' */
  format?: OutputFormat;
  /** @default 'draco' */
  compression?: Compression;
  /** @default 14 */
  quantize_position?: number;
}

// ---- answers -------------------------------------------------------------------------------------------------------

export interface Result<T = unknown> {
  status: number;
  contentType: string;
  headers: Headers;
  body: Uint8Array;
  /** the parsed body of a JSON answer, else undefined */
  json: T | undefined;
  text(): string;
}

export interface RepairReport {
  welded?: number; degenerate?: number; duplicate?: number; flipped?: number; nonmanifold_split?: number;
  small_components?: number; removed_faces?: number; holes_filled?: number; fill_faces?: number;
  unreferenced?: number; components?: number;
}

/** The JSON answer (format 'json') of the mesh operations and implicitMesh. */
export interface MeshAnswer {
  mesh: Mesh;
  stats: {
    input_vertices?: number; input_faces?: number; output_vertices?: number; output_faces?: number;
    elapsed_ms?: number; repairs?: RepairReport; [stat: string]: unknown;
  };
}

export interface PatchesAnswer { patches: Patch[] }

export interface PointcloudAnswer {
  points: Vec3[];
  normals?: Vec3[];
  colors?: number[][];
  stats: { points?: number; elapsed_ms?: number };
}

export interface ImplicitQueryAnswer {
  kind?: 'exact_distance' | 'distance_bound' | 'general';
  lipschitz?: number | null;
  points?: { class: 'inside' | 'on' | 'outside' | 'undefined'; value: number | null; gradient: number[] | null }[];
  rays?: { hit: boolean; t?: number; point?: number[]; normal?: number[]; steps: number }[];
}

/** Only the answers asked for; a ray that misses has hit false and null for the rest. */
/** With `encoding` float32 or float64 every array below is instead a base64 string of packed values. */
export interface MeshQueryAnswer {
  encoding?: 'float32' | 'float64';
  points?: { inside?: boolean[] | string; winding_number?: number[] | string; distance?: number[] | string;
    closest?: number[][] | string; face?: number[] | string };
  rays?: { hit: boolean[] | string; t: (number | null)[] | string; face: (number | null)[] | string;
    point: (number[] | null)[] | string; normal: (number[] | null)[] | string };
}

/** One member per query asked (evaluate, length, ...); an svg answers per subpath in `subpaths`. */
export type CurvesAnswer = Record<string, unknown>;
/** degree, rational, domain, and one member per query asked (evaluate, closest, elevate, ...). */
export type SurfacesAnswer = Record<string, unknown>;

export interface Problem {
  type?: string; title?: string; status?: number; detail?: string; code?: string; field?: string; line?: number;
  /** what would make the request work ("repair=auto repairs it") */
  hint?: string;
  [member: string]: unknown;
}

export declare class SurfacedError extends Error {
  constructor(status: number, problem: Problem);
  /** the HTTP status; 0: the server could not be reached */
  status: number;
  problem: Problem;
  code?: string;
  field?: string;
  line?: number;
  hint?: string;
}

export declare class IncompatibleServerError extends Error {
  constructor(serverVersion: string, apiVersion?: string);
  serverVersion: string;
  apiVersion: string;
}

export interface ClientOptions {
  /** @default 60000 */
  timeoutMs?: number;
  /** sent as Authorization: Bearer */
  token?: string;
  headers?: Record<string, string>;
}

export interface RequestOptions {
  json?: unknown;
  data?: BodyData;
  contentType?: string;
  query?: Record<string, string | number | boolean | number[] | undefined | null>;
  headers?: Record<string, string>;
}

export declare class Client {
  constructor(baseUrl?: string, options?: ClientOptions);
  baseUrl: string;
  timeoutMs: number;
  headers: Record<string, string>;
  request(method: string, path: string, options?: RequestOptions): Promise<Result>;
  /** info.version of the server's /openapi.json */
  serverVersion(): Promise<string>;
  /** the server's API version; throws IncompatibleServerError when this client was not made for it */
  checkServerVersion(): Promise<string>;
  healthz(): Promise<{ status: 'ok' }>;
  livez(): Promise<{ status: 'ok' }>;
  readyz(): Promise<{ status: 'ready' }>;
  metrics(): Promise<string>;
  openapi(): Promise<Record<string, any>>;
  subdivide(options: SubdivideOptions): Promise<Result<MeshAnswer>>;
  simplify(options: SimplifyOptions): Promise<Result<MeshAnswer>>;
  remesh(options: RemeshOptions): Promise<Result<MeshAnswer>>;
  repair(options: RepairOptions): Promise<Result<MeshAnswer>>;
  tessellate(options: TessellateOptions): Promise<Result<never>>;
  patchSample(name?: string, options?: PatchSampleOptions): Promise<Result<PatchesAnswer>>;
  curves(options: CurvesOptions): Promise<Result<CurvesAnswer>>;
  surfaces(options: SurfacesOptions): Promise<Result<SurfacesAnswer>>;
  implicitQuery(options: ImplicitQueryOptions): Promise<Result<ImplicitQueryAnswer>>;
  meshQuery(options: MeshQueryOptions): Promise<Result<MeshQueryAnswer>>;
  limitEvaluate(options: LimitEvaluateOptions): Promise<Result<LimitEvaluateAnswer>>;
  implicitGrid(options: ImplicitGridOptions): Promise<Result<LevelSetNode>>;
  implicitMesh(options: ImplicitMeshOptions): Promise<Result<MeshAnswer>>;
  pointcloud(options: PointcloudOptions): Promise<Result<PointcloudAnswer>>;
  reconstruct(options: ReconstructOptions): Promise<Result<MeshAnswer>>;
}
