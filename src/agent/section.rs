//! An agent's configuration section, owned by the agent: its type (with its defaults, range
//! checks and the settings rows the page shows of it, `AgentConfig`) lives in the agent's
//! module, and the agent table's row names it by its JSON key (`SectionSpec`). A run's configuration holds one section per key of the table
//! (`experiment::RunConfig::section`), so adding an agent with parameters touches no file of
//! the runs layer, and the core hands each agent its own section without naming its type.

use crate::arena::ConfigError;
use crate::param::Param;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::any::Any;
use std::fmt;

/// What an agent's configuration section can do, type-erased: checked, written as JSON, copied
/// and compared. Implemented for every type with `AgentConfig` and serde's traits.
pub trait Section: Any + Send + Sync + fmt::Debug + erased_serde::Serialize {
    /// Every field in its range, the error naming it.
    fn validate(&self) -> Result<(), ConfigError>;
    /// Whether a configuration writes it (not a native agent's section no one gave).
    fn written(&self) -> bool {
        true
    }
    /// As the configuration's JSON writes it.
    fn to_value(&self) -> serde_json::Value;
    /// A copy.
    fn clone_box(&self) -> Box<dyn Section>;
    /// Whether `other` is the same type with the same values.
    fn same(&self, other: &dyn Section) -> bool;
    /// Itself, to be read as its own type.
    fn as_any(&self) -> &dyn Any;
    /// Itself, to be changed as its own type.
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// What an agent declares of its configuration: its range checks and the settings the page, Python
/// and the CLI show of it (each row with its range, help, group, and whether a change acts live,
/// which `Controller::reconfigure` then applies).
pub trait AgentConfig {
    /// Its key in a configuration's JSON (`agent` for SEC's, as the committed configurations
    /// spell it).
    const KEY: &'static str;

    /// Its TypeScript declaration, merged into the page's `RunConfig` interface: `export
    /// interface RunConfig { <KEY>?: { ... } }`. The agent's module also hands it to
    /// wasm-bindgen (a `typescript_custom_section`), and `tests/typescript.rs` checks it against
    /// what the section serialises. A native crate's section, which the page never holds,
    /// declares none.
    const TYPESCRIPT: &'static str = "";

    /// Every field in its range, the error naming it.
    fn validate(&self) -> Result<(), ConfigError>;

    /// Its settings rows, in the order the page shows them (none by default).
    fn settings() -> Vec<SectionSetting>
    where
        Self: Sized,
    {
        Vec::new()
    }
}

/// Reads a setting's value from a section, as the URL hash writes it.
pub type GetSetting = Box<dyn Fn(&dyn Any) -> String + Send + Sync>;
/// Sets a setting's value, already parsed and range-checked (`Param::kind`): the number, the
/// choice's index, 1 or 0 for a switch.
pub type SetSetting = Box<dyn Fn(&mut dyn Any, f64) + Send + Sync>;

/// One setting of an agent's section: what the page shows, and how it reads and writes it.
pub struct SectionSetting {
    /// The row as the page shows it (its `agents` are filled in from the table).
    pub param: Param,
    /// Its value in a section.
    pub get: GetSetting,
    /// Sets it in a section.
    pub set: SetSetting,
}

impl SectionSetting {
    /// The row `param` of the section type `T`, read by `get` and written by `set`.
    pub fn of<T: Any>(param: Param, get: fn(&T) -> String, set: fn(&mut T, f64)) -> SectionSetting {
        let wrong = || -> ! { panic!("a setting of {} was handed another section", std::any::type_name::<T>()) };
        SectionSetting {
            param,
            get: Box::new(move |s| get(s.downcast_ref::<T>().unwrap_or_else(|| wrong()))),
            set: Box::new(move |s, v| set(s.downcast_mut::<T>().unwrap_or_else(|| wrong()), v)),
        }
    }
}

impl<T> Section for T
where
    T: AgentConfig + Serialize + Clone + PartialEq + fmt::Debug + Send + Sync + 'static,
{
    fn validate(&self) -> Result<(), ConfigError> {
        AgentConfig::validate(self)
    }
    fn to_value(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("configuration sections serialise")
    }
    fn clone_box(&self) -> Box<dyn Section> {
        Box::new(self.clone())
    }
    fn same(&self, other: &dyn Section) -> bool {
        other.as_any().downcast_ref::<T>().is_some_and(|o| o == self)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// The section of a native agent whose crate this build does not hold (DQN's and ERLAM's in
/// the wasm build and in Python): kept as the configuration wrote it, so reading and writing a
/// configuration loses nothing, but neither checked nor filled in, since nothing here runs it.
/// A native crate registers its own type for the key (`register_section`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NativeSection(Option<serde_json::Value>);

impl Section for NativeSection {
    fn validate(&self) -> Result<(), ConfigError> {
        Ok(())
    }
    fn written(&self) -> bool {
        self.0.is_some()
    }
    fn to_value(&self) -> serde_json::Value {
        self.0.clone().unwrap_or(serde_json::Value::Null)
    }
    fn clone_box(&self) -> Box<dyn Section> {
        Box::new(self.clone())
    }
    fn same(&self, other: &dyn Section) -> bool {
        other.as_any().downcast_ref::<NativeSection>().is_some_and(|o| o == self)
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

fn native_default() -> Box<dyn Section> {
    Box::new(NativeSection(None))
}

fn native_parse(key: &'static str, value: serde_json::Value) -> Result<Box<dyn Section>, ConfigError> {
    if !value.is_object() {
        return Err(ConfigError::new(
            key,
            format!("{} is not an object (a section)", crate::util::shown(&value.to_string())),
        ));
    }
    Ok(Box::new(NativeSection(Some(value))))
}

fn native_parse_text(key: &'static str, text: &str) -> Result<Box<dyn Section>, ConfigError> {
    let found = serde::de::DeserializeSeed::deserialize(
        Pick::<serde_json::Value>(key, std::marker::PhantomData),
        &mut serde_json::Deserializer::from_str(text),
    )
    .map_err(|e| ConfigError::new(key, e.to_string()))?;
    found.map_or_else(|| Ok(native_default()), |v| native_parse(key, v))
}

fn no_settings() -> Vec<SectionSetting> {
    Vec::new()
}

/// The sections native crates registered, each replacing its row's `SectionSpec::native`.
static REGISTERED: std::sync::RwLock<Vec<SectionSpec>> = std::sync::RwLock::new(Vec::new());

/// Gives the section under `spec.key`, which a table row declares `SectionSpec::native`, its
/// type: configurations made after this read, check, fill in and write it as that type. A native
/// crate calls it before it reads configurations (`sec_dqn::register`); again is harmless.
pub fn register_section(spec: SectionSpec) {
    let mut held = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    held.retain(|s| s.key != spec.key);
    held.push(spec);
}

/// The type registered for a native section's key, if any.
pub(crate) fn registered(key: &str) -> Option<SectionSpec> {
    REGISTERED.read().unwrap_or_else(|e| e.into_inner()).iter().find(|s| s.key == key).copied()
}

/// Whether two sections under `key` are the same settings. A native section held opaque
/// (made before its crate registered its type, or read where it never does) is read through
/// the registered type if there is one, so it compares with its defaults filled in.
pub fn same_settings(key: &str, a: &dyn Section, b: &dyn Section) -> bool {
    if a.same(b) {
        return true;
    }
    let Some(spec) = registered(key) else { return false };
    let typed = |s: &dyn Section| match s.as_any().downcast_ref::<NativeSection>() {
        Some(NativeSection(value)) => {
            (spec.parse)(spec.key, value.clone().unwrap_or_else(|| serde_json::Value::Object(Default::default()))).ok()
        }
        None => Some(s.clone_box()),
    };
    matches!((typed(a), typed(b)), (Some(x), Some(y)) if x.same(y.as_ref()))
}

erased_serde::serialize_trait_object!(Section);

impl Clone for Box<dyn Section> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

impl PartialEq for Box<dyn Section> {
    fn eq(&self, other: &Self) -> bool {
        self.same(other.as_ref())
    }
}

/// Reads a section's JSON under its key (the key names the fields of its errors).
pub type ParseSection = fn(&'static str, serde_json::Value) -> Result<Box<dyn Section>, ConfigError>;

/// Reads a section from a whole configuration's JSON text, where it sits under its key: errors
/// carry their line and column in that text as well as the field's path.
pub type ParseSectionText = fn(&'static str, &str) -> Result<Box<dyn Section>, ConfigError>;

/// How the core reads an agent's section: its JSON key in a configuration, its defaults and its
/// parser (a value of another shape is an error naming the field by its path, `agent.memory.tau`).
#[derive(Clone, Copy)]
pub struct SectionSpec {
    /// Its key in a configuration's JSON (`agent` for SEC's, as the committed configurations
    /// spell it).
    pub key: &'static str,
    /// The section with the agent's defaults.
    pub default: fn() -> Box<dyn Section>,
    /// The section read from its JSON (missing fields take the defaults), not yet validated.
    pub parse: ParseSection,
    /// The section read from a configuration's text (`parse`, with positions in its errors).
    pub parse_text: ParseSectionText,
    /// Its settings rows (`AgentConfig::settings`).
    pub settings: fn() -> Vec<SectionSetting>,
    /// Its TypeScript declaration (`AgentConfig::TYPESCRIPT`).
    pub typescript: &'static str,
}

impl fmt::Debug for SectionSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "SectionSpec({})", self.key)
    }
}

impl Serialize for SectionSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.key)
    }
}

fn default_of<T: Section + Default>() -> Box<dyn Section> {
    Box::new(T::default())
}

fn parse_as<T: Section + DeserializeOwned>(
    key: &'static str,
    value: serde_json::Value,
) -> Result<Box<dyn Section>, ConfigError> {
    let section: T = serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let field = if path == "." { key.to_string() } else { format!("{key}.{path}") };
        ConfigError::new(field, e.inner().to_string())
    })?;
    Ok(Box::new(section))
}

/// Reads the value under one key of a JSON object, passing over the others.
struct Pick<T>(&'static str, std::marker::PhantomData<T>);

impl<'de, T: serde::Deserialize<'de>> serde::de::DeserializeSeed<'de> for Pick<T> {
    type Value = Option<T>;
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<Option<T>, D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de, T: serde::Deserialize<'de>> serde::de::Visitor<'de> for Pick<T> {
    type Value = Option<T>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an object (a RunConfig)")
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Option<T>, A::Error> {
        let mut found = None;
        while let Some(key) = map.next_key::<String>()? {
            if key == self.0 {
                found = Some(map.next_value::<T>()?);
            } else {
                map.next_value::<serde::de::IgnoredAny>()?;
            }
        }
        Ok(found)
    }
}

fn parse_text_as<T: Section + Default + DeserializeOwned>(
    key: &'static str,
    text: &str,
) -> Result<Box<dyn Section>, ConfigError> {
    let mut de = serde_json::Deserializer::from_str(text);
    let mut track = serde_path_to_error::Track::new();
    let seed = Pick::<T>(key, std::marker::PhantomData);
    let section =
        serde::de::DeserializeSeed::deserialize(seed, serde_path_to_error::Deserializer::new(&mut de, &mut track))
            .map_err(|e| {
                let path = track.path().to_string();
                ConfigError::new(if path == "." { key.to_string() } else { path }, e.to_string())
            })?;
    Ok(Box::new(section.unwrap_or_default()))
}

impl SectionSpec {
    /// The section of a native agent (one a crate under `crates/` builds): opaque to the core
    /// until that crate registers its type (`register_section`).
    pub const fn native(key: &'static str) -> SectionSpec {
        SectionSpec {
            key,
            typescript: "",
            default: native_default,
            parse: native_parse,
            parse_text: native_parse_text,
            settings: no_settings,
        }
    }

    /// The section of type `T`, under its key.
    pub const fn of<T: Section + AgentConfig + Default + DeserializeOwned>() -> SectionSpec {
        SectionSpec {
            key: T::KEY,
            typescript: T::TYPESCRIPT,
            default: default_of::<T>,
            parse: parse_as::<T>,
            parse_text: parse_text_as::<T>,
            settings: T::settings,
        }
    }
}

/// An agent's own section as its type, from the section a run hands its builder and
/// `Controller::reconfigure` (the core passes each agent the section its table row names,
/// without knowing its type). Another type is an error naming the section.
pub fn own_section<'a, T: Any>(section: &'a dyn Any, key: &str) -> Result<&'a T, ConfigError> {
    section
        .downcast_ref::<T>()
        .ok_or_else(|| ConfigError::new(key, format!("is not this agent's section (a {})", std::any::type_name::<T>())))
}
