#pragma once
// Exports of a BatchModel for 3D-city and BIM handoff, and the CityJSON read-back.
//
// Conventions shared by every format (see also DESIGN.md, "Elements"):
//  - coordinates: CityGML/CityJSON carry world coordinates (local + frame.origin,
//    millimetre resolution); IFC, OBJ and STEP carry coordinates local to
//    frame.origin (IFC georeferences them with IfcMapConversion + IfcProjectedCRS,
//    OBJ with an offset file beside each OBJ: float32 readers keep local metres to
//    the sub-millimetre, world UTM northings only to 1 m).
//  - party walls are real walls, so CityGML/CityJSON write them as WallSurface with
//    the attribute isPartyWall = true (ClosureSurface is reserved for virtual
//    surfaces); IFC writes IfcWall .USERDEFINED. with ObjectType 'PartyWall'.
//  - each surface is stored once per LoD (docs/exports.md): the closed solid carries
//    the element surfaces, and what of an element lies outside it (roof overhangs,
//    hanging roofs, outer ceilings) is a separate surface of the same element, so a
//    sum of the surfaces by type equals the store's element totals.
//  - a building whose roof elements have clearly distinct eave heights (> 1 m apart)
//    becomes one BuildingPart per roof level in CityGML; the closed solid stays on
//    the Building (CityJSON: a roof_level on each semantic surface).
//  - lower LoDs (Building::lower_lods) are written beside the primary one.
//  - identifiers are derived from building ids and element positions only, so a rerun
//    writes identical ids (IFC GlobalIds included).
// Every writer throws std::runtime_error when the file cannot be written.
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

struct ParcelValuation;

// A writer fed a page of parcels at a time, so an export of any size needs the
// memory of one page (docs/exports.md, "Streamed"). Pages come in layer order
// and share the header's frame and CRS; finish() writes what needs every page
// (an envelope, CityJSON's vertex list, IFC's project aggregation), closes the
// file and returns the files written. Temporary files sit beside the output.
class ExportWriter {
 public:
  virtual ~ExportWriter() = default;
  virtual void add(const BatchModel& page) = 0;
  // Whether the writer carries the parcels' values (3D Tiles); those are given
  // the next page's valuations before add(page).
  virtual bool carries_values() const { return false; }
  virtual void values(const std::vector<ParcelValuation>&) {}
  virtual std::vector<std::string> finish() = 0;
};
// The writer of one format name (see export_formats) into dir; `header` gives
// the frame and CRS (its parcels are not written). Throws std::invalid_argument
// on an unknown name.
std::unique_ptr<ExportWriter> export_writer(const std::string& format, const BatchModel& header,
                                            const std::string& dir,
                                            std::vector<std::string>* skipped = nullptr);
// The writers themselves (path: the file; OBJ and STEP: the folder).
std::unique_ptr<ExportWriter> citygml_writer(const BatchModel& header, const std::string& path, int version);
std::unique_ptr<ExportWriter> cityjson_writer(const BatchModel& header, const std::string& path);
std::unique_ptr<ExportWriter> cityjson_seq_writer(const BatchModel& header, const std::string& path);
std::unique_ptr<ExportWriter> ifc_writer(const BatchModel& header, const std::string& path);
// 3D Tiles 1.1 into the folder dir: tileset.json and tiles/*.glb (tile_content.h).
// Throws std::runtime_error when the header has no CRS.
std::unique_ptr<ExportWriter> tileset_writer(const BatchModel& header, const std::string& dir);

// CityGML 2.0 (version 2) or 3.0 (version 3, on GML 3.2): the same content.
void write_citygml(const BatchModel& model, const std::string& path, int version = 2);
void write_cityjson(const BatchModel& model, const std::string& path);
// CityJSONSeq (CityJSON Text Sequence): a first line holding the CityJSON header
// (transform, metadata, no objects), then one CityJSONFeature per building with
// its own vertices, written building by building.
void write_cityjson_seq(const BatchModel& model, const std::string& path);
void write_ifc(const BatchModel& model, const std::string& path);
// One <parcel id>.obj per parcel with buildings (groups per element), each with
// <parcel id>.offset.json (world = local + offset, CRS) and, where the CRS is
// known, <parcel id>.prj beside it; returns the .obj files.
std::vector<std::string> write_obj_per_parcel(const BatchModel& model, const std::string& dir);
// One <building id>.step per building solid (OpenCASCADE B-rep); returns the files.
// A solid OpenCASCADE cannot build throws, or with `skipped` is listed there
// ("<building id>: <why>") and left out.
std::vector<std::string> write_step_per_building(const BatchModel& model, const std::string& dir,
                                                 std::vector<std::string>* skipped = nullptr);

// The format names export_formats() accepts: gml (CityGML 2.0), gml3 (CityGML
// 3.0), cityjson, cityjsonseq, ifc, obj, step, 3dtiles.
const std::vector<std::string>& export_format_names();
// Writes the named formats into dir as buildings.gml, buildings.citygml3.gml,
// buildings.city.json, buildings.city.jsonl, buildings.ifc, obj/, step/, 3dtiles/; returns
// the paths.
// Buildings whose STEP solid fails are listed in `skipped` when given (else it throws).
// Throws std::invalid_argument on an unknown format name.
std::vector<std::string> export_formats(const BatchModel& model, const std::string& dir,
                                        const std::vector<std::string>& formats,
                                        std::vector<std::string>* skipped = nullptr);

// Reads a CityJSON file written by write_cityjson (or any CityJSON 2.0 file with
// Building / BuildingPart objects) back into a BatchModel: at the highest LoD,
// elements from the semantic surfaces (by element_index, of the Solid and the
// MultiSurface), the solid from the Solid; lower LoDs' Solids as lower_lods.
// Throws c3d::InputError on malformed files and out-of-range vertex indices.
BatchModel read_cityjson(const std::string& path);

}  // namespace c3d
