#pragma once
// Former name of cadastre/sql_db.h (the store's connection over SQLite or PostgreSQL).
#include "cadastre/sql_db.h"
