// The PostgreSQL + PostGIS store (issue 37): `batch --store postgresql://...`
// writes the same LADM store as the GeoPackage, many writers at once, a
// killed batch resumes without duplicates, and a bad location is one line.
// PostgreSQL comes from scripts/services.sh; each test has its own database.
// Skipped with a message where PostgreSQL is not running (in CI: failed).
#include <gtest/gtest.h>

#include <fstream>

#include <array>
#include <cmath>
#include <cstdio>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "tests/batch_e2e_support.h"
#include "tests/shared_store_checks.h"
#include "tests/store_fixtures.h"
#include "valuation/valuation.h"

namespace {

using namespace c3d;
namespace fs = std::filesystem;

// stdout of a shell command (stderr dropped), and its exit status.
std::string shell(const std::string& cmd, int* rc = nullptr) { return test::shell(cmd + " 2>/dev/null", rc); }

// A TCP port on 127.0.0.1 that nothing was bound to a moment ago (the kernel's pick).
int free_tcp_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  const bool ok = fd >= 0 && bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
                  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0;
  if (fd >= 0) close(fd);
  return ok ? ntohs(addr.sin_port) : 55400 + getpid() % 90;
}

// The server's base URL (database cadastre3d) of scripts/services.sh, which
// CTest's fixture Services.StartPostgres starts before these tests (never
// they: started by tests running at once, it raced); "" when it does not answer.
const std::string& server_url() {
  static const std::string url = [] {
    const std::string script = std::string(C3D_SOURCE_DIR) + "/scripts/services.sh";
    std::string env = shell("bash " + script + " env");
    const auto at = env.find("C3D_PG_URL=");
    if (at == std::string::npos) return std::string();
    std::string u = env.substr(at + 11, env.find('\n', at) - at - 11);
    int rc = 1;
    shell("psql '" + u + "' -qtAc 'SELECT postgis_lib_version()'", &rc);
    return rc == 0 ? u : std::string();
  }();
  return url;
}

// A database of this test's own, dropped at the end.
class PgDatabase {
 public:
  explicit PgDatabase(const std::string& name) : name_(name + "_" + std::to_string(getpid())) {
    base_ = server_url().substr(0, server_url().rfind('/'));
    psql("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    psql("CREATE DATABASE " + name_);
    url_ = base_ + "/" + name_;
  }
  ~PgDatabase() { psql("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)"); }
  const std::string& url() const { return url_; }
  // One number from a query in this database.
  double number(const std::string& query) const {
    return std::atof(shell("psql '" + url_ + "' -qtAc \"" + query + "\"").c_str());
  }

 private:
  void psql(const std::string& sql) { shell("psql '" + server_url() + "' -qtAc '" + sql + "'"); }
  std::string name_, base_, url_;
};

// The URL as messages show it: the password masked.
std::string masked(std::string url) {
  const auto at = url.find(":secret@");
  return at == std::string::npos ? url : url.replace(at, 8, ":***@");
}

#define REQUIRE_POSTGRES()                                                                      \
  C3D_NEED(!server_url().empty(), "PostgreSQL + PostGIS not running (ctest starts it in Services.StartPostgres; " \
                                  "by hand: scripts/services.sh start)")

struct Town {
  std::string dir, gpkg;  // the sample town and its batch into a GeoPackage
};

// A 12-parcel sample town, batched once into a GeoPackage: the reference.
const Town& town() {
  static const Town t = [] {
    Town t;
    t.dir = test::temp_dir("postgis_town");
    e2e::make_town(t.dir + "/town", 12, 3, "--density 10 --wall-density 5");
    std::string out;
    const int rc = test::run_cli(e2e::batch_args(t.dir + "/town", t.dir + "/gpkg") + " --formats cityjson --quiet", &out);
    EXPECT_TRUE(rc == 0 || rc == 3) << out;
    t.gpkg = t.dir + "/gpkg/cadastre.gpkg";
    return t;
  }();
  return t;
}

std::string pg_batch(const std::string& url, const std::string& out, const std::string& extra = "") {
  return e2e::batch_args(town().dir + "/town", out) + " --store " + url + " --formats cityjson --quiet " + extra;
}

// Equal stores (issue 37): the same parcels and statuses, element areas to
// 1e-6 m², valuations (NJOP, tax) to 1e-6.
void expect_same_store(const std::string& a, const std::string& b) {
  // Matched by parcel id: a writer of a --where subset numbers its parcels within it.
  const BatchModel ma = load_batch_model(a), mb = load_batch_model(b);
  ASSERT_EQ(ma.parcels.size(), mb.parcels.size());
  EXPECT_EQ(ma.epsg, mb.epsg);
  std::map<std::string, size_t> in_b;
  for (size_t i = 0; i < mb.parcels.size(); ++i) in_b[mb.parcels[i].id] = i;
  for (size_t i = 0; i < ma.parcels.size(); ++i) {
    const std::string& id = ma.parcels[i].id;
    ASSERT_EQ(in_b.count(id), 1u) << id;
    const size_t j = in_b[id];
    EXPECT_EQ(ma.results[i].status, mb.results[j].status) << id;
    EXPECT_NEAR(area(ma.parcels[i].shape), area(mb.parcels[j].shape), 1e-6) << id;
    ASSERT_EQ(ma.results[i].buildings.size(), mb.results[j].buildings.size()) << id;
    for (size_t k = 0; k < ma.results[i].buildings.size(); ++k) {
      const Building &x = ma.results[i].buildings[k], &y = mb.results[j].buildings[k];
      EXPECT_EQ(x.id, y.id);
      EXPECT_NEAR(x.volume, y.volume, 1e-6) << x.id;
      EXPECT_EQ(x.lower_lods.size(), y.lower_lods.size()) << x.id;
      ASSERT_EQ(x.elements.size(), y.elements.size()) << x.id;
      for (size_t e = 0; e < x.elements.size(); ++e) {
        EXPECT_EQ(x.elements[e].type, y.elements[e].type) << x.id << " element " << e;
        EXPECT_NEAR(x.elements[e].area, y.elements[e].area, 1e-6) << x.id << " element " << e;
        double fa = 0, fb = 0;
        for (const Face& f : x.elements[e].faces) fa += area(f);
        for (const Face& f : y.elements[e].faces) fb += area(f);
        EXPECT_NEAR(fa, fb, 1e-6) << x.id << " faces of element " << e;
      }
    }
  }
  std::map<std::string, ParcelValuation> vb;
  for (const ParcelValuation& v : load_valuations(b)) vb[v.parcel_id] = v;
  const auto va = load_valuations(a);
  ASSERT_EQ(va.size(), vb.size());
  for (const ParcelValuation& v : va) {
    ASSERT_EQ(vb.count(v.parcel_id), 1u) << v.parcel_id;
    EXPECT_NEAR(v.njop, vb[v.parcel_id].njop, 1e-6) << v.parcel_id;
    EXPECT_NEAR(v.tax, vb[v.parcel_id].tax, 1e-6) << v.parcel_id;
    EXPECT_EQ(v.items.size(), vb[v.parcel_id].items.size()) << v.parcel_id;
  }
}

const char* const kLayers[] = {"parcel", "building_footprint", "roof_part", "la_spatialunit",
                               "building", "building_element", "building_lod", "parcel_job"};

void expect_same_counts(const PgDatabase& db, const std::string& gpkg) {
  for (const char* t : kLayers)
    EXPECT_EQ(db.number(std::string("SELECT count(*) FROM ") + t),
              test::sql_number(gpkg, std::string("SELECT count(*) FROM ") + t))
        << t;
  // No parcel twice, none left pending.
  EXPECT_EQ(db.number("SELECT count(*) - count(DISTINCT parcel_id) FROM la_spatialunit"), 0);
  EXPECT_EQ(db.number("SELECT count(*) FROM parcel_job WHERE status = 'pending'"), 0);
}

TEST(PostgisStore, SameAsTheGeoPackage) {
  REQUIRE_POSTGRES();
  PgDatabase db("c3d_test_same");
  std::string out;
  const int rc = test::run_cli(pg_batch(db.url(), town().dir + "/pg_same"), &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  expect_same_store(town().gpkg, db.url());
  expect_same_counts(db, town().gpkg);
  // QGIS: the layers with their types and SRID, and the default styles.
  EXPECT_EQ(db.number("SELECT count(*) FROM geometry_columns WHERE srid = 32748 AND type = 'MULTIPOLYGON'"), 7);
  EXPECT_EQ(db.number("SELECT count(*) FROM geometry_columns WHERE coord_dimension = 3"), 3);
  EXPECT_EQ(db.number("SELECT count(*) FROM layer_styles WHERE f_table_catalog = current_database() AND "
                      "useasdefault AND styleqml IS NOT NULL"),
            2);
  // report --store URL reads the same as from the GeoPackage.
  ASSERT_EQ(test::run_cli("report --store " + db.url() + " --out " + town().dir + "/rep_pg", &out), 0) << out;
  ASSERT_EQ(test::run_cli("report --store " + town().gpkg + " --out " + town().dir + "/rep_gpkg", &out), 0) << out;
  EXPECT_EQ(e2e::read_file(town().dir + "/rep_pg/report.csv"), e2e::read_file(town().dir + "/rep_gpkg/report.csv"));
  ASSERT_EQ(test::run_cli("export --store " + db.url() + " --out " + town().dir + "/exp_pg --formats cityjson", &out), 0)
      << out;
  EXPECT_TRUE(fs::exists(town().dir + "/exp_pg/buildings.city.json"));
  // validate URL judges the same buildings as from the GeoPackage.
  std::string from_gpkg;
  const int rc_pg = test::run_cli("validate " + db.url(), &out);
  EXPECT_EQ(rc_pg, test::run_cli("validate " + town().gpkg, &from_gpkg)) << out;
  EXPECT_EQ(out, from_gpkg);
  EXPECT_NE(out.find(" buildings, "), std::string::npos) << out;
}

TEST(PostgisStore, TwoWritersAtOnce) {
  REQUIRE_POSTGRES();
  PgDatabase db("c3d_test_two");
  const std::string d = town().dir;
  // Disjoint halves of the layer by parcel id, written at the same time.
  const std::string half_a = "--where NIB<='10280503000006'", half_b = "--where NIB>'10280503000006'";
  const pid_t a = e2e::spawn_cli(pg_batch(db.url(), d + "/two_a", half_a), d + "/two_a.log");
  const pid_t b = e2e::spawn_cli(pg_batch(db.url(), d + "/two_b", half_b), d + "/two_b.log");
  for (pid_t p : {a, b}) {
    int status = 0;
    waitpid(p, &status, 0);
    const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    EXPECT_TRUE(rc == 0 || rc == 3) << e2e::read_file(d + (p == a ? "/two_a.log" : "/two_b.log"));
  }
  EXPECT_EQ(db.number("SELECT count(*) FROM run WHERE finished IS NOT NULL"), 2);  // one run row per writer
  EXPECT_EQ(db.number("SELECT count(*) FROM run a JOIN run b ON a.fid < b.fid "
                      "WHERE a.started < b.finished AND b.started < a.finished"),
            1)
      << "the two writers did not run at the same time";
  // The reference: the same halves one after the other into a GeoPackage (a
  // half models its edge buildings without the other half's parcels, so the
  // whole layer's run is no reference here; sharding handles that edge).
  std::string out;
  fs::remove_all(d + "/two_gpkg");  // from an earlier repeat
  const std::string args = e2e::batch_args(d + "/town", d + "/two_gpkg") + " --formats cityjson --quiet ";
  auto quoted = [](const std::string& w) { return "--where \"" + w.substr(8) + "\""; };  // through the shell
  int rc = test::run_cli(args + quoted(half_a), &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  rc = test::run_cli(args + quoted(half_b) + " --resume", &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  expect_same_store(d + "/two_gpkg/cadastre.gpkg", db.url());
  expect_same_counts(db, d + "/two_gpkg/cadastre.gpkg");
  // Each writer's report (what the store held as it ended) and one from the
  // store: every parcel once, the store's twelve in the last.
  ASSERT_EQ(test::run_cli("report --store " + db.url() + " --out " + d + "/two_rep", &out), 0) << out;
  for (const char* dir : {"/two_a", "/two_b", "/two_rep"}) {
    std::map<std::string, int> parcels;
    for (const auto& row : test::parse_csv(e2e::read_file(d + dir + "/report.csv")))
      if (row[0] == "parcel") ++parcels[row[1]];
    EXPECT_GE(parcels.size(), 6u) << dir;
    for (const auto& [id, n] : parcels) EXPECT_EQ(n, 1) << id << " in " << dir;
    if (std::string(dir) == "/two_rep") EXPECT_EQ(parcels.size(), 12u);
  }
}

// Two writers of the same parcels with other settings (a tax rate of 0.002
// for 0.001) started at once: the first to claim the store writes it, the
// other is refused in one line and writes nothing (before, both passed the
// check and the store mixed them). Three times: the order is the race's.
TEST(PostgisStore, WritersOfOtherSettingsAtOnceNeverMix) {
  REQUIRE_POSTGRES();
  const std::string d = town().dir, config = d + "/rate2.toml";
  {
    std::string toml = e2e::read_file(std::string(C3D_SOURCE_DIR) + "/config/cadastre3d.toml");
    toml.replace(toml.find("\nrate = 0.001"), 13, "\nrate = 0.002");
    std::ofstream(config) << toml;
  }
  for (int round = 0; round < 3; ++round) {
    PgDatabase db("c3d_test_mix");
    const pid_t a = e2e::spawn_cli(pg_batch(db.url(), d + "/mix_a"), d + "/mix_a.log");
    const pid_t b = e2e::spawn_cli(pg_batch(db.url(), d + "/mix_b", "--config " + config), d + "/mix_b.log");
    int written = 0, refused = 0;
    for (pid_t p : {a, b}) {
      int status = 0;
      waitpid(p, &status, 0);
      const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      const std::string log = e2e::read_file(d + (p == a ? "/mix_a.log" : "/mix_b.log"));
      written += rc == 0 || rc == 3;
      refused += rc == 1 && log.find("parcel(s) of another run") != std::string::npos;
    }
    EXPECT_EQ(written, 1) << "round " << round;
    EXPECT_EQ(refused, 1) << "round " << round;
    EXPECT_EQ(db.number("SELECT count(*) FROM run"), 1) << "the refused writer left no run record";
    EXPECT_EQ(db.number("SELECT count(DISTINCT run_id) FROM parcel_job"), 1) << "every parcel of one run";
    EXPECT_EQ(db.number("SELECT count(DISTINCT tax_rate) FROM vm_valuation"), 1) << "one tax rate in the store";
  }
}

// The pages of a database two writers of different selections share: the
// parcels counted, each once, whatever the other writer adds meanwhile.
TEST(PostgisStore, PagesOfASharedStoreHoldTheCountedParcelsOnce) {
  REQUIRE_POSTGRES();
  PgDatabase db("c3d_test_pages");
  test::expect_pages_fixed_once(db.url(), test::temp_dir("pages") + "/report");
}

TEST(PostgisStore, KilledThenResumed) {
  REQUIRE_POSTGRES();
  PgDatabase db("c3d_test_kill");
  const std::string d = town().dir;
  const pid_t p = e2e::spawn_cli(pg_batch(db.url(), d + "/kill", "--jobs 1"), d + "/kill.log");
  // Kill once a few parcels are stored, before all are.
  for (int k = 0; k < 600; ++k) {
    if (db.number("SELECT count(*) FROM parcel_job WHERE status <> 'pending'") >= 3) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(p, SIGKILL);
  waitpid(p, nullptr, 0);
  const double done = db.number("SELECT count(*) FROM parcel_job WHERE status <> 'pending'");
  EXPECT_GE(done, 3);
  EXPECT_LT(done, 12) << "the batch ended before it was killed";
  // Whole parcels only: every stored spatial unit has its finished job.
  EXPECT_EQ(db.number("SELECT count(*) FROM la_spatialunit su JOIN parcel_job j USING (parcel_id) "
                      "WHERE j.status = 'pending'"),
            0);
  // As a store from before run_input had a role: resuming adds the column.
  db.number("ALTER TABLE run_input DROP COLUMN role");
  std::string out;
  const int rc = test::run_cli(pg_batch(db.url(), d + "/kill", "--resume"), &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  expect_same_store(town().gpkg, db.url());
  expect_same_counts(db, town().gpkg);
  // The roles round-trip: the resumed run's are the GeoPackage's; the killed run's unknown.
  const auto roles = [](const RunRecord& r) {
    std::vector<std::string> out;
    for (const InputFile& f : r.inputs) out.push_back(f.role);
    return out;
  };
  const std::vector<RunRecord> runs = load_runs(db.url());
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(roles(runs[0]), std::vector<std::string>(runs[0].inputs.size(), ""));
  EXPECT_EQ(roles(runs[1]), roles(load_runs(town().gpkg).back()));
  EXPECT_EQ(roles(runs[1]), (std::vector<std::string>{"cloud", "parcels", "dtm"}));
}

// The library's Store on PostGIS with a CRS that has no EPSG code: its own
// spatial_ref_sys row; every vertex and number comes back bit for bit as from
// the GeoPackage; another CRS into the same database is refused.
TEST(PostgisStore, CustomCrsAndExactRoundTrip) {
  REQUIRE_POSTGRES();
  PgDatabase db("c3d_test_crs");
  const std::string wkt =
      "PROJCS[\"Cimahi local TM\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
      "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],"
      "PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",107.5],PARAMETER[\"scale_factor\",1],"
      "PARAMETER[\"false_easting\",500000],PARAMETER[\"false_northing\",10000000],UNIT[\"metre\",1]]";
  BatchModel m = test::sample_batch(2);
  m.epsg = 0;
  const std::string gpkg = test::temp_dir("postgis_crs") + "/ref.gpkg";
  for (const std::string& loc : {gpkg, db.url()}) {
    Store s;
    s.open(loc, wkt, 0);
    s.begin_run("{}", {}, m.frame);
    for (size_t i = 0; i < m.parcels.size(); ++i)
      s.write_parcel(m.parcels[i], m.results[i], value_parcel(m.parcels[i], m.results[i], default_config().valuation),
                     m.frame);
    s.end_run();
  }
  EXPECT_EQ(db.number("SELECT count(*) FROM geometry_columns WHERE srid = 100000"), 7);
  EXPECT_EQ(db.number("SELECT count(*) FROM spatial_ref_sys WHERE srid = 100000 AND auth_name = 'cadastre3d'"), 1);
  const BatchModel a = load_batch_model(gpkg), b = load_batch_model(db.url());
  EXPECT_EQ(b.epsg, 0);
  EXPECT_EQ(b.crs_wkt, wkt);
  ASSERT_EQ(a.parcels.size(), b.parcels.size());
  for (size_t i = 0; i < a.parcels.size(); ++i) {
    EXPECT_EQ(a.parcels[i].shape[0].outer, b.parcels[i].shape[0].outer);
    EXPECT_EQ(a.results[i].reason, b.results[i].reason);
    ASSERT_EQ(a.results[i].buildings.size(), b.results[i].buildings.size());
    for (size_t k = 0; k < a.results[i].buildings.size(); ++k) {
      const Building &x = a.results[i].buildings[k], &y = b.results[i].buildings[k];
      EXPECT_EQ(x.solid.size(), y.solid.size());
      for (size_t f = 0; f < x.solid.size(); ++f) EXPECT_EQ(x.solid[f].ring, y.solid[f].ring);
      EXPECT_EQ(x.roof_deviation.rmse, y.roof_deviation.rmse);
      EXPECT_EQ(x.volume, y.volume);
      EXPECT_EQ(x.terrain_z, y.terrain_z);
      for (size_t e = 0; e < x.elements.size(); ++e) EXPECT_EQ(x.elements[e].area, y.elements[e].area);
    }
  }
  Store other;
  try {
    other.open(db.url(), "", 32748);
    ADD_FAILURE() << "a store of another CRS was opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("SRID 100000"), std::string::npos) << e.what();
  }
}

// One line naming the store, exit 1, for each way the location can be wrong.
TEST(PostgisStore, BadLocationIsOneLine) {
  REQUIRE_POSTGRES();
  const std::string port = server_url().substr(server_url().rfind(':') + 1, 5);
  const std::string bad[] = {
      "postgresql://postgres@127.0.0.1:1/nowhere",                        // nothing listens
      "postgresql://postgres@127.0.0.1:" + port + "/c3d_no_such_database",  // no such database
      "postgresql://no_such_user:secret@127.0.0.1:" + port + "/cadastre3d", // no such role
      "postgresql://postgres@127.0.0.1:notaport/x",                       // malformed URL
  };
  for (const std::string& url : bad) {
    std::string out;
    const int rc = test::run_cli(pg_batch(url, town().dir + "/bad"), &out);
    EXPECT_EQ(rc, 1) << url << "\n" << out;
    std::string lines;
    for (size_t at = 0; (at = out.find('\n', at)) != std::string::npos; ++at) lines += '.';
    EXPECT_LE(lines.size(), 1u) << out;
    EXPECT_NE(out.find(masked(url)), std::string::npos) << out;
    EXPECT_EQ(out.find("secret"), std::string::npos) << "the password is shown: " << out;
  }
}

// A server that asks for a password (a small cluster of the test's own, the
// shared one trusts localhost): a wrong one is one line naming the store.
TEST(PostgisStore, WrongPasswordIsOneLine) {
  REQUIRE_POSTGRES();
  const std::string bin = "/usr/lib/postgresql/15/bin", dir = test::temp_dir("pw_cluster");
  const std::string as = getuid() == 0 ? "runuser -u postgres -- " : "";
  int rc = 1;
  shell("echo right > " + dir + "/pw && chmod 755 " + dir + " && chmod 644 " + dir + "/pw" +
            (getuid() == 0 ? " && chown -R postgres: " + dir : "") + " && " + as + bin + "/initdb -D " + dir +
            "/data -U postgres --auth=scram-sha-256 --pwfile=" + dir + "/pw",
        &rc);
  C3D_NEED(rc == 0, "initdb of a password-checking PostgreSQL cluster in " << dir << " failed");
  // A port the kernel has just handed out is free; another process may take
  // it before the server binds, so a few tries.
  std::string port;
  for (int attempt = 0; attempt < 4; ++attempt) {
    port = std::to_string(free_tcp_port());
    shell(as + bin + "/pg_ctl -D " + dir + "/data -l " + dir + "/log -w -o '-p " + port + " -k " + dir +
              " -c listen_addresses=127.0.0.1' start",
          &rc);
    if (rc == 0) break;
  }
  C3D_NEED(rc == 0, "could not start a password-checking PostgreSQL cluster in "
                        << dir << ":\n" << shell("tail -n 5 " + dir + "/log"));
  std::string out;
  const std::string url = "postgresql://postgres:secret@127.0.0.1:" + port + "/postgres";
  EXPECT_EQ(test::run_cli(pg_batch(url, town().dir + "/pw"), &out), 1) << out;
  EXPECT_NE(out.find(masked(url) + ": cannot connect to the PostgreSQL store"), std::string::npos) << out;
  EXPECT_NE(out.find("password authentication failed"), std::string::npos) << out;
  EXPECT_EQ(out.find("secret"), std::string::npos) << "the password is shown: " << out;
  shell(as + bin + "/pg_ctl -D " + dir + "/data -m fast stop");
}

// GDAL's spelling of a PostgreSQL source, PG: and libpq's keywords, is the
// same store as its URL; nothing is written under its name.
TEST(PostgisStore, GdalConnectionStringIsTheStore) {
  REQUIRE_POSTGRES();
  PgDatabase db("c3d_pg_form");
  // postgresql://user@host:port/name -> PG:host=... port=... dbname=... user=...
  const std::string& u = db.url();
  const size_t at = u.find('@'), colon = u.find(':', at), slash = u.find('/', at);
  const size_t user = u.find("//") + 2;
  const std::string pg = "PG:host=" + u.substr(at + 1, colon - at - 1) +
                         " port=" + u.substr(colon + 1, slash - colon - 1) + " dbname=" + u.substr(slash + 1) +
                         " user=" + u.substr(user, at - user);
  std::string out;
  const std::string dir = test::temp_dir("pg_form");
  const int rc = test::run_cli(pg_batch("'" + pg + "'", dir + "/out"), &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  EXPECT_FALSE(fs::exists(pg)) << "a GeoPackage named after the connection string";
  expect_same_store(town().gpkg, pg);
  expect_same_counts(db, town().gpkg);
}

// What reads as a connection but is none this reads is refused in one line,
// and no GeoPackage is written under its name.
TEST(PostgisStore, OtherConnectionsAreRefused) {
  const std::string dir = test::temp_dir("pg_refused");
  for (const std::string& loc : {std::string("mysql://root@localhost/cadastre"),
                                 std::string("dbname=cadastre host=localhost password=secret")}) {
    std::string out;
    EXPECT_EQ(test::run_cli(e2e::batch_args(town().dir + "/town", dir + "/out") + " --store '" + loc + "' --quiet",
                            &out),
              1)
        << out;
    EXPECT_NE(out.find("PG:"), std::string::npos) << out;
    EXPECT_EQ(out.find("secret"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(loc)) << loc;
  }
}

}  // namespace
